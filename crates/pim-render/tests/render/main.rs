//! What a person reads: the diagram's and the figures' layout and figures that agree with their tables. One test binary.
#[path = "../svg_layout/mod.rs"]
mod svg_layout;

mod diagram_layout;
mod figure_layout;
mod figures_agree;
mod rectify;
