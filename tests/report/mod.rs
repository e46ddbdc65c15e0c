//! Figures, the HTML report and viewer files.

mod figures;
mod html;
mod viewer;
