//! Figures, the HTML report, viewer files and the thesis-statement script's readings.

mod figures;
mod html;
mod statements;
mod viewer;
