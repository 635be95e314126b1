//! The document types of `fitcase` (what the study of the same name in pim-studies writes).

pub use pim_case::fit_sections::CostChoice;
