//! `--width`, `--height`, `--dpi`: the size and resolution of the figures of every command
//! that draws them (`phase-diagram`, `plot`, `report`), checked into a [`Sizing`].

use crate::figure::{DPIS, HEIGHTS, Sizing, WIDTHS};
use crate::sweep::BadInput;
use clap::Args;

/// The size and resolution of a command's pictures.
#[derive(Debug, Args)]
pub struct FigureSize {
    /// picture width in CSS pixels, 300 to 8000 (default: each figure's own)
    #[arg(long, value_name = "PX")]
    pub width: Option<u32>,
    /// picture height in CSS pixels, 200 to 8000 (default: each figure's own)
    #[arg(long, value_name = "PX")]
    pub height: Option<u32>,
    /// resolution of the PNGs in dots per inch, 24 to 600: 96 gives one pixel per CSS pixel,
    /// 192 twice as many each way (for print); SVGs are vector
    #[arg(long, default_value_t = 96.0)]
    pub dpi: f64,
}

impl FigureSize {
    /// The sizing asked for; a value out of range is bad input naming the option and what is
    /// allowed.
    pub fn sizing(&self) -> Result<Sizing, BadInput> {
        for (name, v, range) in [
            ("--width", self.width, WIDTHS),
            ("--height", self.height, HEIGHTS),
        ] {
            if let Some(v) = v
                && !range.contains(&v)
            {
                return Err(BadInput(format!(
                    "{name} {v} is out of range: allowed {} to {} (CSS pixels)",
                    range.start(),
                    range.end()
                )));
            }
        }
        if !(self.dpi.is_finite() && DPIS.contains(&self.dpi)) {
            return Err(BadInput(format!(
                "--dpi {} is out of range: allowed {} to {}",
                self.dpi,
                DPIS.start(),
                DPIS.end()
            )));
        }
        Ok(Sizing {
            width: self.width,
            height: self.height,
            dpi: self.dpi,
        })
    }
}
