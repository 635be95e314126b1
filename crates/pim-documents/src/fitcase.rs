//! The document types of `fitcase` (what the study of the same name in pim-studies writes).

use pim_fit::CostPreset;

/// What `--cost` selects: a preset, or the case's own known / estimated components.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostChoice {
    /// Q1, Q2 or Q3 from `[estimates]`.
    Preset(CostPreset),
    /// `[known]` held fixed, `[estimates]` estimated, everything else unknown.
    Custom,
}

impl CostChoice {
    /// `q1`, `q2`, `q3`, or `custom` for the case's own cost.
    pub fn name(self) -> &'static str {
        match self {
            CostChoice::Preset(p) => p.name(),
            CostChoice::Custom => "custom",
        }
    }
}

impl serde::Serialize for CostChoice {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

pim_core::json_schema_as!(CostChoice, {"type": "string", "description": "The cost function: its name as the case file writes it."});
