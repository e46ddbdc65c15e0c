//! The engine boundary: an engine plugs in at one place (docs/architecture.md, "Adding an
//! engine"), and the engine layer imports nothing above itself.

mod plugin;
