//! What a geometry fit estimates and reports: the inputs, their bounds, and the estimate.

use pim_core::{Collision, Vehicle};
use serde::{Deserialize, Serialize};

/// An input of the impact geometry that a fit may estimate. Vehicles are numbered 1 and 2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum GeometryInput {
    /// Distance from the vehicle's CG to the impact centre, m.
    D(u8),
    /// Angle from the vehicle's nose to the impact centre, degrees counter-clockwise.
    Phi(u8),
    /// The impact centre's coordinate along the vehicle's forward axis, m.
    X(u8),
    /// The impact centre's coordinate along the vehicle's left axis, m.
    Y(u8),
    /// The crush-surface angle Gamma, degrees.
    CrushAngle,
}

impl GeometryInput {
    /// The name used in case files and reports: `vehicle1.d`, `vehicle2.impact_point.x`,
    /// `crush_angle`.
    pub fn name(self) -> String {
        match self {
            GeometryInput::D(v) => format!("vehicle{v}.d"),
            GeometryInput::Phi(v) => format!("vehicle{v}.phi"),
            GeometryInput::X(v) => format!("vehicle{v}.impact_point.x"),
            GeometryInput::Y(v) => format!("vehicle{v}.impact_point.y"),
            GeometryInput::CrushAngle => "crush_angle".into(),
        }
    }

    pub(crate) fn vehicle(self) -> Option<u8> {
        match self {
            GeometryInput::D(v)
            | GeometryInput::Phi(v)
            | GeometryInput::X(v)
            | GeometryInput::Y(v) => Some(v),
            GeometryInput::CrushAngle => None,
        }
    }

    /// Whether the input named `name` (as [`GeometryInput::name`] writes it) is a distance, m
    /// (an impact centre's d or coordinate), rather than an angle, degrees.
    ///
    /// ```
    /// use pim_fit::GeometryInput;
    /// assert!(GeometryInput::name_is_length(&GeometryInput::D(1).name()));
    /// assert!(GeometryInput::name_is_length(&GeometryInput::X(2).name()));
    /// assert!(!GeometryInput::name_is_length(&GeometryInput::CrushAngle.name()));
    /// ```
    pub fn name_is_length(name: &str) -> bool {
        name.ends_with(".d") || name.contains("impact_point")
    }

    /// The input's value in a collision.
    pub fn get(self, c: &Collision) -> f64 {
        let xy = |v: &Vehicle| pim_core::impact_point_cartesian(v.d, v.phi);
        match self {
            GeometryInput::D(v) => vehicle(c, v).d,
            GeometryInput::Phi(v) => vehicle(c, v).phi,
            GeometryInput::X(v) => xy(vehicle(c, v)).0,
            GeometryInput::Y(v) => xy(vehicle(c, v)).1,
            GeometryInput::CrushAngle => c.crush_angle,
        }
    }

    /// Sets the input's value in a collision (the impact centre stays in polar form).
    pub fn set(self, c: &mut Collision, value: f64) {
        let set_xy = |v: &mut Vehicle, x: Option<f64>, y: Option<f64>| {
            let (x0, y0) = pim_core::impact_point_cartesian(v.d, v.phi);
            let (d, phi) = pim_core::impact_point_polar(x.unwrap_or(x0), y.unwrap_or(y0));
            v.d = d;
            v.phi = phi;
        };
        match self {
            GeometryInput::D(v) => vehicle_mut(c, v).d = value,
            GeometryInput::Phi(v) => vehicle_mut(c, v).phi = value,
            GeometryInput::X(v) => set_xy(vehicle_mut(c, v), Some(value), None),
            GeometryInput::Y(v) => set_xy(vehicle_mut(c, v), None, Some(value)),
            GeometryInput::CrushAngle => c.crush_angle = value,
        }
    }
}

fn vehicle(c: &Collision, v: u8) -> &Vehicle {
    if v == 1 {
        &c.vehicle1
    } else {
        &c.vehicle2
    }
}

fn vehicle_mut(c: &mut Collision, v: u8) -> &mut Vehicle {
    if v == 1 {
        &mut c.vehicle1
    } else {
        &mut c.vehicle2
    }
}

/// One estimated geometry input and its bounds `[low, high]` (m or degrees). The problem's
/// collision gives the start, which must lie within them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct GeometryBound {
    /// The input.
    pub input: GeometryInput,
    /// `[low, high]`.
    pub bounds: [f64; 2],
}

/// The impact centre of one vehicle in polar form.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CentreEstimate {
    /// CG to impact centre, m.
    pub d: f64,
    /// From the nose, degrees counter-clockwise.
    pub phi: f64,
}

/// How well the data pin down one geometry input: the values along a scan through the optimum
/// (the other inputs held) whose cost is within the identifiability tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct GeometryRange {
    /// The input's name (as in [`GeometryInput::name`]).
    pub input: String,
    /// The estimate.
    pub value: f64,
    /// The bounds searched.
    pub bounds: [f64; 2],
    /// Smallest scanned value within the tolerance.
    pub low: f64,
    /// Largest such value.
    pub high: f64,
    /// The relative cost tolerance used (the fit's identifiability tolerance).
    pub tolerance: f64,
    /// False when that range covers half of the bounds or more: the data do not determine the
    /// input within the bounds.
    pub identifiable: bool,
    /// The estimate lies on a bound (within 0.1 % of the range): the bound, not the data, ends
    /// it.
    pub at_bound: bool,
}

/// What the search over the geometry did, for one branch.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct GeometrySearch {
    /// The method, in words.
    pub method: String,
    /// Grid points per input.
    pub points_per_input: usize,
    /// Grid points evaluated (with the case's own geometry).
    pub grid_points: usize,
    /// Nelder-Mead refinements over the geometry.
    pub refinements: usize,
    /// Complete coefficient fits run for this branch (grid, refinements, scans, proof).
    pub fits: usize,
    /// What is proven about the optimum over the box.
    pub proof: GeometryProof,
}

/// What is proven about a branch's optimum over the geometry box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ProofStatus {
    /// The reported geometry's cost is within the tolerance of the optimum over the box.
    Proven,
    /// No geometry within the bounds admits an answer.
    ProvenInfeasible,
    /// The branch-and-bound stopped at its limit of boxes: the optimum over the box lies
    /// between the proven lower bound and the reported cost.
    Bounded,
    /// The bound is not written for this problem (see the reason): the geometry is the best
    /// found.
    NotAttempted,
}

/// The proof of the optimum over the geometry box (branch-and-bound over boxes of the
/// estimated inputs, each bounded below by weak duality; see the crate docs).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct GeometryProof {
    /// What is proven.
    pub status: ProofStatus,
    /// A proven lower bound of the branch's optimal cost over the whole box (`None` when not
    /// attempted; infinite when no geometry admits an answer).
    pub lower: Option<f64>,
    /// The tolerance of "proven": the reported cost exceeds `lower` by at most
    /// `max(tolerance cost, absolute)`.
    pub tolerance: f64,
    /// The absolute floor of the tolerance, in units of the cost: 1e-6 of `1 + sum w t^2` of the
    /// data (the fit's own floor for comparing costs).
    pub absolute: f64,
    /// Boxes bounded.
    pub boxes: usize,
    /// Why the proof was not attempted or stopped.
    pub reason: Option<String>,
}

impl GeometryProof {
    /// The proof in words, given the reported cost (`None`: no answer).
    pub fn statement(&self, cost: Option<f64>) -> String {
        let lower = self.lower.unwrap_or(f64::NEG_INFINITY);
        match self.status {
            ProofStatus::Proven => format!(
                "the geometry is proven optimal over its bounds to a relative {:e} of the cost or \
                 {:.1e} absolute, whichever is larger (lower bound {lower:.6}; branch-and-bound \
                 over {} boxes)",
                self.tolerance, self.absolute, self.boxes
            ),
            ProofStatus::ProvenInfeasible => format!(
                "no geometry within the bounds admits an answer (proven over {} boxes)",
                self.boxes
            ),
            ProofStatus::Bounded if cost.is_none() => {
                format!(
                "no geometry the search tried admits an answer; that none within the bounds does \
                 is not proven ({})",
                self.reason.as_deref().unwrap_or("the branch-and-bound stopped")
            )
            }
            ProofStatus::Bounded => {
                format!(
                "the geometry is the best found over its bounds; the optimum over them is proven \
                 at least {lower:.6}{} ({})",
                cost.map_or(String::new(), |c| format!(
                    " (relative gap {:.2e})",
                    (c - lower) / c.abs().max(1e-300)
                )),
                self.reason.as_deref().unwrap_or("the branch-and-bound stopped")
            )
            }
            ProofStatus::NotAttempted => format!(
                "the geometry is the best found over its bounds, not proven ({})",
                self.reason
                    .as_deref()
                    .unwrap_or("no bound for this problem")
            ),
        }
    }

    /// Whether the optimum over the geometry is proven (or proven not to exist).
    pub fn is_proven(&self) -> bool {
        matches!(
            self.status,
            ProofStatus::Proven | ProofStatus::ProvenInfeasible
        )
    }
}

/// The estimated geometry of one branch.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct GeometryEstimate {
    /// Vehicle 1's impact centre.
    pub vehicle1: CentreEstimate,
    /// Vehicle 2's impact centre.
    pub vehicle2: CentreEstimate,
    /// The crush-surface angle, degrees.
    pub crush_angle: f64,
    /// Identifiability of each estimated input, in the order given.
    pub ranges: Vec<GeometryRange>,
    /// The search.
    pub search: GeometrySearch,
}

impl GeometryEstimate {
    /// Writes the estimated impact centres and crush-surface angle into a collision.
    pub fn apply(&self, c: &mut Collision) {
        c.vehicle1.d = self.vehicle1.d;
        c.vehicle1.phi = self.vehicle1.phi;
        c.vehicle2.d = self.vehicle2.d;
        c.vehicle2.phi = self.vehicle2.phi;
        c.crush_angle = self.crush_angle;
    }

    /// The checked collision of `base` at this geometry ([`impact_at`]).
    ///
    /// # Errors
    /// pim-core's, for a collision it cannot take.
    pub fn impact(&self, base: &pim_core::Impact) -> pim_core::Result<pim_core::Impact> {
        let mut c = *base.collision();
        self.apply(&mut c);
        impact_at(base, c)
    }

    /// The number of inputs estimated (with bounds that leave them room).
    pub fn estimated_inputs(&self) -> usize {
        self.ranges
            .iter()
            .filter(|r| r.bounds[1] > r.bounds[0])
            .count()
    }
}

/// The collision `c` checked, as a geometry of `base`: a side of the crush surface that `base`
/// states holds at every geometry; otherwise each reads its own.
///
/// # Errors
/// pim-core's, for a collision it cannot take.
pub fn impact_at(
    base: &pim_core::Impact,
    c: pim_core::Collision,
) -> pim_core::Result<pim_core::Impact> {
    let impact = pim_core::Impact::new(c)?;
    Ok(if base.side_is_fixed() {
        impact.with_side(base.side())
    } else {
        impact
    })
}
