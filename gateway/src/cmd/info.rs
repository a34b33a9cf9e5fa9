//! `info`: the `initialization` result (number of axes, version, cycle time, axis limits).
//! It takes no arguments; parsing is in `Command::parse`, the result in `crate::result`.
