//! # pim-render: what the PIM toolkit shows a person
//!
//! Tables, the report of a crash (HTML and Markdown), the scale plan-view diagram and the SVG figures of the `pim`
//! command, shared by every front end (the command line and the Python package), so that each
//! draws and prints exactly the same thing. Everything is returned as text: an SVG document, a
//! table, a CSV or Markdown string, a DXF drawing's bytes; the caller writes files.
//!
//! ```text
//!   pim-core  (equations, reports)        pim-fit (fit reports)        pim-studies (cases, records)
//!        \__________________________________|________________________________/
//!                                           |
//!                                      pim-render
//!      tables (text tables and the words shared by every output)
//!      report (the document of a crash: HTML and Markdown from one content; build, html)
//!      momentum (the momentum diagram)
//!      batch_tables (summary, models, costs, Brach 1984 Table 1, intervals, CSV)
//!      diagram (plan view at contact: outlines, C, crush surface, velocities, impulses)
//!      figures (batch), uncertainty_figures, predict_figure (plotters, SVG strings)
//!      runout (the scene to scale), cad (the same plan as a DXF drawing, by layer)
//!                                           |
//!                         pim-cli (the `pim` binary), pim-py (Python)
//! ```
//!
//! Numbers are printed in the unit system the caller asks for ([`pim_case::units::UnitSystem`]);
//! the JSON documents, made by pim-studies, stay SI.

pub mod batch_tables;
pub mod cad;
pub mod damage;
pub mod damage_batch;
pub mod diagram;
pub mod figures;
mod geometry_lines;
mod ground;
pub mod momentum;
pub mod plan;
pub mod predict_figure;
pub mod reconstruct;
pub mod rectify;
pub mod report;
pub mod runout;
mod runout_plan;
mod runout_table;
pub mod solved;
pub mod speed_history;
pub mod statistics;
pub mod tables;
pub mod text;
pub mod uncertainty_figures;

/// An SVG figure: its file name (e.g. `cost.svg`) and its text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Figure {
    /// File name, without a folder.
    pub name: String,
    /// The SVG document.
    pub svg: String,
}

/// Why a figure, a drawing or a table could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    /// The plotting library failed (its message): an SVG could not be drawn.
    #[error("cannot draw: {0}")]
    Draw(String),
    /// A number to draw is not finite (what holds it).
    #[error("cannot draw: {0} is not a finite number")]
    NotFinite(&'static str),
    /// There is nothing to draw (what is missing).
    #[error("nothing to draw: {0}")]
    Nothing(&'static str),
    /// The impact of a case cannot be set up for its diagram.
    #[error("the impact: {0}")]
    Impact(pim_core::PimError),
    /// A table could not be written as CSV (the writer's message).
    #[error("cannot write the CSV: {0}")]
    Csv(String),
    /// The case, or an answer of it, cannot be drawn (located, as the studies say it).
    #[error(transparent)]
    Input(#[from] pim_studies::documents::DocumentError),
}

impl RenderError {
    /// The message, naming the case file `file` where the error does not already (the
    /// studies' errors are located).
    pub fn in_file(&self, file: &str) -> String {
        match self {
            RenderError::Input(e) => e.to_string(),
            e => format!("{file}: {e}"),
        }
    }
}

/// A CSV writer's error as a [`RenderError::Csv`].
pub(crate) fn csv_error<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError::Csv(e.to_string())
}

/// A plotting error as a [`RenderError::Draw`] (the figures' error).
pub(crate) fn err<E: std::fmt::Display>(e: E) -> RenderError {
    RenderError::Draw(e.to_string())
}

/// A figure drawn by `draw` on a white SVG canvas of `size` pixels.
pub(crate) fn svg_figure(
    name: &str,
    size: (u32, u32),
    draw: impl FnOnce(
        &plotters::drawing::DrawingArea<plotters::prelude::SVGBackend<'_>, plotters::coord::Shift>,
    ) -> Result<(), crate::RenderError>,
) -> Result<Figure, crate::RenderError> {
    use plotters::prelude::*;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(crate::err)?;
        draw(&root)?;
        root.present().map_err(crate::err)?;
    }
    Ok(Figure {
        name: name.into(),
        svg,
    })
}
