//! Everything the command shows a person: tables, CSV files and SVG figures.

pub mod batch_tables;
pub mod diagram;
pub mod figures;
pub mod markdown;
pub mod tables;
pub mod uncertainty_figures;
