//! The report of one crash: a document written once and rendered twice, as a self-contained
//! HTML page (figures inline; opens in any browser and prints to PDF) and as Markdown beside
//! the figure files.
//!
//! [`build`] assembles the content from a solve or a fit (and, when one was run, the
//! uncertainty study): the answer with its ranges, the residual of every estimate and
//! observation, the fit statistics, what the data do not determine, every warning, the
//! figures, the method and the inputs as given. [`Document::html`] and
//! [`Document::markdown`] print the same numbers: both render the same cells.

pub mod build;
mod damage_section;
mod doc;
mod fit_sections;
mod html;
pub mod make;
pub mod scene;

pub use doc::{Block, Document, Section, Table};
