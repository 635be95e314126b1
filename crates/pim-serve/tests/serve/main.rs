//! The scene editor's server: its answers, the contact tool, the forms, the figures beside their tables and the saves that never lose the user's work. One test binary.

mod answer;
mod contact;
mod figures_print_the_table;
mod form;
mod writes;
