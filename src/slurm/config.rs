//! The cluster limits granflow reads from `scontrol show config` (no accounting needed).

use anyhow::{Context, Result, bail};
use std::process::Command;

/// Slurm's default `MaxArraySize` (array indices run from 0 to MaxArraySize - 1).
pub const DEFAULT_MAX_ARRAY_SIZE: usize = 1001;

/// Read `MaxArraySize` from the output of `scontrol show config`; `None` if the key is absent.
///
/// The lines look like `MaxArraySize            = 1001`.
pub fn parse_max_array_size(config: &str) -> Result<Option<usize>> {
    for line in config.lines() {
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        if key.trim() == "MaxArraySize" {
            let value = value.trim();
            let size: usize = value
                .parse()
                .with_context(|| format!("MaxArraySize in `scontrol show config` is '{value}'"))?;
            if size == 0 {
                bail!("MaxArraySize in `scontrol show config` is 0: job arrays are disabled");
            }
            return Ok(Some(size));
        }
    }
    Ok(None)
}

/// Ask the controller for `MaxArraySize` (one `scontrol show config` call).
pub fn query_max_array_size() -> Result<usize> {
    let out = Command::new("scontrol")
        .args(["show", "config"])
        .output()
        .context("running `scontrol show config` (is Slurm's client installed and on PATH?)")?;
    if !out.status.success() {
        bail!(
            "`scontrol show config` failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    Ok(parse_max_array_size(&text)?.unwrap_or(DEFAULT_MAX_ARRAY_SIZE))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_max_array_size_among_other_keys() {
        let text = "Configuration data as of 2026-11-23T11:52:10\n\
                    MailProg                = /bin/mail\n\
                    MaxArraySize            = 40001\n\
                    MaxJobCount             = 10000\n";
        assert_eq!(parse_max_array_size(text).unwrap(), Some(40001));
        assert_eq!(parse_max_array_size("MaxJobCount = 5\n").unwrap(), None);
    }

    #[test]
    fn rejects_zero_and_garbage() {
        assert!(parse_max_array_size("MaxArraySize = 0").is_err());
        let err = parse_max_array_size("MaxArraySize = lots").unwrap_err();
        assert!(format!("{err:#}").contains("lots"));
    }
}
