//! The DSMC engine (Gupta 2017).

mod channel;
mod sweep;
