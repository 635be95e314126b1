//! What a case says of itself and of its vehicles, resolved: its title, each vehicle as loaded
//! (SI, the natural frame, a barrier filled in, a yaw inertia estimated from the outline where
//! the file leaves it out), and whether it asks for an uncertainty study.

use crate::case::{Case, VehicleSection};

impl Case {
    /// The case's title (`title = ...`), where it gives one.
    pub fn title(&self) -> Option<&str> {
        self.content.title.as_deref()
    }

    /// The title for a document's heading: the case's own, else its file.
    pub fn heading(&self) -> String {
        self.title()
            .map_or_else(|| self.file.clone(), str::to_string)
    }

    /// Vehicle `k` (0 or 1), resolved.
    pub fn vehicle(&self, k: usize) -> &VehicleSection {
        self.content.vehicle(k)
    }

    /// Both vehicles, resolved.
    pub fn vehicles(&self) -> [&VehicleSection; 2] {
        [&self.content.vehicle1, &self.content.vehicle2]
    }

    /// Both vehicles' descriptions, where the case gives both.
    pub fn descriptions(&self) -> Option<(&str, &str)> {
        let c = &self.content;
        match (&c.vehicle1.description, &c.vehicle2.description) {
            (Some(a), Some(b)) => Some((a, b)),
            _ => None,
        }
    }

    /// The plan's background image (`[background]`), where the case gives one.
    pub fn background(&self) -> Option<&crate::scene_sections::BackgroundSection> {
        self.content.background.as_ref()
    }

    /// Vehicle `k`'s (0 or 1) rest tyre points as written (`[scene.vehicleN] rest_tyres`: the
    /// case's units and frame), `(x, y)` each: where an edit of the rest moves them from.
    pub fn rest_tyres_written(&self, k: usize) -> Vec<(f64, f64)> {
        self.content
            .scene
            .as_ref()
            .and_then(|s| if k == 0 { &s.vehicle1 } else { &s.vehicle2 }.as_ref())
            .map(|s| s.rest_tyres.iter().map(|t| (t.x, t.y)).collect())
            .unwrap_or_default()
    }

    /// True when the case gives standard deviations (`[sigma]`) or spreads (`[uncertainty]`):
    /// it asks for an uncertainty study by default.
    pub fn is_uncertain(&self) -> bool {
        self.content.sigma.is_some() || self.content.uncertainty.is_some()
    }
}
