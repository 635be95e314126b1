//! The report as data: a title, sections and their blocks, and its Markdown rendering.

use crate::Figure;

/// A report: a title, lines under it and sections.
#[derive(Debug, Clone, PartialEq)]
pub struct Document {
    /// The title (the case's title, or its file name).
    pub title: String,
    /// Lines under the title: what was done, to which file.
    pub subtitle: Vec<String>,
    /// The sections, in order.
    pub sections: Vec<Section>,
}

/// A section: a heading and its blocks.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    /// The heading.
    pub heading: String,
    /// The content.
    pub blocks: Vec<Block>,
}

/// One block of a section.
#[derive(Debug, Clone, PartialEq)]
pub enum Block {
    /// A paragraph of plain text.
    Text(String),
    /// A bulleted list.
    List(Vec<String>),
    /// Warnings: a list shown so that it cannot be missed.
    Warnings(Vec<String>),
    /// A table.
    Table(Table),
    /// A figure with its caption (inline in HTML; a link to the file in Markdown).
    Figure(Figure, String),
    /// A file as given, verbatim: its name and text.
    Source(String, String),
}

/// A table of text cells; numeric columns are right-aligned.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The column headings.
    pub head: Vec<String>,
    /// The rows, each as long as `head`.
    pub rows: Vec<Vec<String>>,
    /// Which columns hold numbers (right-aligned).
    pub numeric: Vec<bool>,
}

impl Table {
    /// A table with these headings; the first column is text, the others numbers.
    pub fn new(head: &[&str]) -> Self {
        Table {
            head: head.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
            numeric: (0..head.len()).map(|k| k > 0).collect(),
        }
    }

    /// Adds a row.
    pub fn row(&mut self, cells: Vec<String>) {
        debug_assert_eq!(cells.len(), self.head.len());
        self.rows.push(cells);
    }
}

impl Section {
    /// An empty section with this heading.
    pub fn new(heading: &str) -> Self {
        Section {
            heading: heading.into(),
            blocks: Vec::new(),
        }
    }

    /// Adds a paragraph.
    pub fn text(&mut self, t: impl Into<String>) -> &mut Self {
        self.blocks.push(Block::Text(t.into()));
        self
    }
}

impl Document {
    /// The figures of the document, in order (written beside the Markdown).
    pub fn figures(&self) -> Vec<&Figure> {
        self.sections
            .iter()
            .flat_map(|s| &s.blocks)
            .filter_map(|b| match b {
                Block::Figure(f, _) => Some(f),
                _ => None,
            })
            .collect()
    }

    /// The document as Markdown; figures are linked by their file names.
    pub fn markdown(&self) -> String {
        use std::fmt::Write as _;
        let mut s = format!("# {}\n\n", self.title);
        for line in &self.subtitle {
            let _ = writeln!(s, "{line}\n");
        }
        for sec in &self.sections {
            let _ = writeln!(s, "## {}\n", sec.heading);
            for b in &sec.blocks {
                match b {
                    Block::Text(t) => {
                        let _ = writeln!(s, "{t}\n");
                    }
                    Block::List(items) => {
                        for i in items {
                            let _ = writeln!(s, "- {i}");
                        }
                        s.push('\n');
                    }
                    Block::Warnings(items) => {
                        for i in items {
                            let _ = writeln!(s, "- **warning:** {i}");
                        }
                        s.push('\n');
                    }
                    Block::Table(t) => {
                        let cell = |c: &str| c.replace('|', "\\|");
                        let head: Vec<String> = t.head.iter().map(|h| cell(h)).collect();
                        let _ = writeln!(s, "| {} |", head.join(" | "));
                        let rule: Vec<&str> = t
                            .numeric
                            .iter()
                            .map(|n| if *n { "---:" } else { "---" })
                            .collect();
                        let _ = writeln!(s, "|{}|", rule.join("|"));
                        for r in &t.rows {
                            let r: Vec<String> = r.iter().map(|c| cell(c)).collect();
                            let _ = writeln!(s, "| {} |", r.join(" | "));
                        }
                        s.push('\n');
                    }
                    Block::Figure(f, caption) => {
                        let _ = writeln!(s, "![{caption}]({})\n\n*{caption}*\n", f.name);
                    }
                    Block::Source(name, text) => {
                        let _ = writeln!(s, "`{name}`:\n\n```toml\n{}\n```\n", text.trim_end());
                    }
                }
            }
        }
        s
    }
}
