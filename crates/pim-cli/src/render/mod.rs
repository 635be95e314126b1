//! Everything the command shows a person: tables, CSV files and SVG figures.

pub mod batch_tables;
pub use pim_cli::diagram;
pub mod figures;
pub mod markdown;
pub mod predict_figure;
pub mod tables;
pub mod uncertainty_figures;
