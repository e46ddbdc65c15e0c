//! Text in figures: widths measured in the figure font, lines wrapped to a width, and the
//! heading band atop a figure (title lines in a band of their own height).

use super::Scale;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The width in CSS pixels of `text` in the figure font at `size` CSS pixels (its glyphs'
/// advances, as the PNGs lay it out).
pub fn width(text: &str, size: f64) -> f64 {
    super::raster::advance(text, size)
}

/// Split `text` into lines no wider than `max` CSS pixels at `size`, breaking after ", "
/// where possible and at spaces within a part too wide for a line of its own.
pub fn wrap(text: &str, size: f64, max: f64) -> Vec<String> {
    let fits = |s: &str| width(s, size) <= max;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    let push = |lines: &mut Vec<String>, line: &mut String| {
        let done = line.trim_end().to_string();
        if !done.is_empty() {
            lines.push(done);
        }
        line.clear();
    };
    for (i, part) in text.split(", ").enumerate() {
        let sep = if i == 0 { "" } else { ", " };
        if fits(&format!("{line}{sep}{part}")) {
            line.push_str(sep);
            line.push_str(part);
            continue;
        }
        if !line.is_empty() {
            line.push(',');
            push(&mut lines, &mut line);
        }
        if fits(part) {
            line.push_str(part);
            continue;
        }
        // a part too wide for a line: break it at spaces
        for word in part.split(' ') {
            if line.is_empty() || fits(&format!("{line} {word}")) {
                if !line.is_empty() {
                    line.push(' ');
                }
                line.push_str(word);
            } else {
                push(&mut lines, &mut line);
                line.push_str(word);
            }
        }
    }
    push(&mut lines, &mut line);
    lines
}

/// A figure's heading: lines of text above the drawing, each wrapped to the figure's width;
/// the first in the larger size.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Heading {
    pub lines: Vec<String>,
}

/// Font sizes and line height of a heading, CSS pixels.
const HEADING_FIRST: f64 = 14.0;
const HEADING_OTHER: f64 = 13.0;
const HEADING_LINE: i32 = 18;
const HEADING_PAD: i32 = 6;
const HEADING_LEFT: i32 = 10;

impl Heading {
    /// The lines as drawn on a figure `width` CSS pixels wide, with their font sizes.
    pub fn wrapped(&self, width: u32) -> Vec<(String, f64)> {
        let max = (f64::from(width) - 2.0 * f64::from(HEADING_LEFT)).max(80.0);
        self.lines
            .iter()
            .enumerate()
            .flat_map(|(i, line)| {
                let size = if i == 0 { HEADING_FIRST } else { HEADING_OTHER };
                wrap(line, size, max).into_iter().map(move |l| (l, size))
            })
            .collect()
    }

    /// Its height in CSS pixels on a figure `width` CSS pixels wide (0 without lines).
    pub fn height(&self, width: u32) -> u32 {
        let n = self.wrapped(width).len() as i32;
        if n == 0 {
            0
        } else {
            (2 * HEADING_PAD + HEADING_LINE * n) as u32
        }
    }

    /// Draw the heading at the top of `root` (`width` CSS pixels wide); the area below it.
    pub fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        width: u32,
        s: Scale,
    ) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
        let lines = self.wrapped(width);
        if lines.is_empty() {
            return Ok(root.clone());
        }
        for (i, (line, size)) in lines.iter().enumerate() {
            root.draw(&Text::new(
                line.clone(),
                s.at((HEADING_LEFT, HEADING_PAD + HEADING_LINE * i as i32)),
                s.font(*size),
            ))?;
        }
        let (_, below) = root.split_vertically(s.px(self.height(width)));
        Ok(below)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_wraps_at_commas_within_the_width() {
        let text = "L/W = 2, W/d = 10, H/d = 10, phi = 0.15, e = 0.7, beta = 0.1, e_w = 0.99";
        let max = width("L/W = 2, W/d = 10, H/d = 10,", 13.0) + 1.0;
        let lines = wrap(text, 13.0, max);
        assert!(lines.len() >= 2, "{lines:?}");
        for l in &lines {
            assert!(width(l, 13.0) <= max, "{l} is wider than {max}");
            assert!(!l.starts_with(' ') && !l.ends_with(' '), "{l:?}");
        }
        // nothing lost but the separators at the breaks
        assert_eq!(lines.join(" "), text);
        // a long part without commas breaks at spaces
        let words = "one two three four five six";
        let max = width("one two", 13.0) + 1.0;
        let lines = wrap(words, 13.0, max);
        assert_eq!(lines[0], "one two");
        assert!(lines.iter().all(|l| width(l, 13.0) <= max), "{lines:?}");
        assert_eq!(lines.join(" "), words);
    }

    #[test]
    fn a_proportional_font_measures_narrow_and_wide_letters_apart() {
        assert!(width("iiii", 13.0) < 0.7 * width("MMMM", 13.0));
    }
}
