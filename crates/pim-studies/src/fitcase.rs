//! Building a fit problem from a case file (`pim fit`): the case's fit sections as pim-case
//! resolves them ([`pim_case::fit_sections`]).

pub use pim_case::fit_sections::*;
