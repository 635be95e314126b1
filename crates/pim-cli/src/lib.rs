//! The scale diagram of the `pim` command as a library, so that other front ends (the Python
//! package) draw exactly what `pim draw` draws. The command itself is the binary `pim`.

pub mod diagram;
