//! Figures on disk: the one place that turns a plotters drawing into a PNG or SVG file (the
//! embedded font, the PNG encoding by the `png` crate, atomic writes). Phase diagrams, the
//! lattice gas' space-time picture, the curve plots and the per-job figures draw; this module
//! renders (to bytes, for pages that inline them) and writes.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// The error of drawing on backend `B`.
pub type DrawingError<B> = DrawingAreaErrorKind<<B as DrawingBackend>::ErrorType>;

/// Register the embedded DejaVu Sans Mono (src/sweep/fonts, free licence) as "sans-serif", so
/// that figures need no system fonts. Call before drawing text.
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("sweep/fonts/DejaVuSansMono.ttf"),
        );
    });
}

/// Encode 8-bit RGB pixels (rows top to bottom) as a PNG.
pub fn encode_png(rgb: &[u8], w: u32, h: u32) -> anyhow::Result<Vec<u8>> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()?;
    }
    Ok(out)
}

/// Draw a `w` x `h` picture on a white bitmap and write it to `path` as PNG (atomically).
pub fn save_png<F>(path: &Path, size: (u32, u32), draw: F) -> anyhow::Result<()>
where
    F: FnOnce(
        &DrawingArea<BitMapBackend<'_>, Shift>,
    ) -> Result<(), DrawingError<BitMapBackend<'static>>>,
{
    let bytes = render_png(size, draw).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    crate::sweep::write_atomic(path, &bytes)?;
    Ok(())
}

/// Draw a `w` x `h` picture on a white bitmap and return it encoded as PNG (for files and for
/// pages that inline their figures).
pub fn render_png<F>((w, h): (u32, u32), draw: F) -> anyhow::Result<Vec<u8>>
where
    F: FnOnce(
        &DrawingArea<BitMapBackend<'_>, Shift>,
    ) -> Result<(), DrawingError<BitMapBackend<'static>>>,
{
    register_font();
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        draw(&root).map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
    }
    encode_png(&buf, w, h)
}

/// Draw a `w` x `h` picture as SVG and write it to `path` (atomically).
pub fn save_svg<F>(path: &Path, size: (u32, u32), draw: F) -> anyhow::Result<()>
where
    F: FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), DrawingError<SVGBackend<'static>>>,
{
    let text = render_svg(size, draw).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    crate::sweep::write_atomic(path, text.as_bytes())?;
    Ok(())
}

/// Draw a `w` x `h` picture as SVG and return its text.
pub fn render_svg<F>(size: (u32, u32), draw: F) -> anyhow::Result<String>
where
    F: FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), DrawingError<SVGBackend<'static>>>,
{
    register_font();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        draw(&root).map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
    }
    Ok(text)
}
