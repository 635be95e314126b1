//! Everything the command shows a person: tables, CSV files and SVG figures.

pub mod batch_tables;
pub mod figures;
pub mod tables;
