//! Numbers in messages as a person reads them: 1e308 as "1e308", not 309 digits.

/// A number as a person reads it: as written where it is short, in scientific notation where
/// its digits would run on (1e308 is "1e308", not 309 digits).
pub fn readable_number(x: f64) -> String {
    let plain = x.to_string();
    if plain.len() <= 16 {
        return plain;
    }
    let short = format!("{x:e}");
    if short.len() <= 10 {
        short
    } else {
        format!("{x:.3e}")
    }
}

/// `text` with every number of more than 16 digits (an engine's message about a value near
/// the largest double) written by [`readable_number`].
pub fn readable_numbers(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        let (before, from) = rest.split_at(start);
        out.push_str(before);
        let len = from
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(from.len());
        let run = from[..len].trim_end_matches('.');
        let glued = before
            .chars()
            .last()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
        let digits = run.chars().filter(char::is_ascii_digit).count();
        match run.parse::<f64>() {
            Ok(x) if digits > 16 && !glued => out.push_str(&readable_number(x)),
            _ => out.push_str(run),
        }
        rest = &from[run.len()..];
    }
    out.push_str(rest);
    out
}
