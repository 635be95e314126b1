//! Reference tables of the papers shipped with the data (`data/reference/`).

/// One row of Brach 1984 Table 1 (`data/reference/brach1984_table1.csv`).
#[derive(Debug, Clone, serde::Deserialize)]
pub struct BrachRow {
    /// A (em free) or B (em = 1).
    pub branch: String,
    /// Test number.
    pub test: u32,
    /// Brach's sum of squares (his units and weights).
    pub sum_of_squares: f64,
    /// Energy loss, percent.
    pub energy_loss_percent: f64,
    /// Restitution.
    pub e: f64,
    /// Moment restitution.
    pub em: f64,
    /// Friction.
    pub mu: f64,
}

/// Parses the Brach 1984 Table 1 reference file.
pub fn parse_brach(text: &str) -> Result<Vec<BrachRow>, csv::Error> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    rdr.deserialize().collect::<Result<Vec<BrachRow>, _>>()
}
