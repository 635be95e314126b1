//! How the plan of a crash lies on the page: the same in every figure of a case (the plan view
//! at contact, the run-out, the scene of a reconstruction), so that one point of the scene is
//! drawn at one place in all of them.
//!
//! - Natural frame (and the papers' geometry; x, y to the left of x, angles counter-clockwise): x to the right, y up, as in
//!   a mathematics text.
//! - SAE frame (x, y to the right of x, angles clockwise): read as a map, x up and y to the right
//!   (a scene diagram with x north has north up and east to the right).
//!
//! Both are rotations of the fixed frame, never reflections: a vehicle turning clockwise on the
//! road turns clockwise on the page. Internally every position is in the natural frame; an SAE
//! point `(x, y_sae)` is `(x, -y_sae)` there, and lies on the page at `(y_sae, x)`, which is the
//! natural point turned 90 degrees counter-clockwise.

use pim_core::Convention;

/// The page of a case's figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Page {
    /// The frame the case is written in.
    pub frame: Convention,
}

impl Page {
    /// The page of a case written in `frame`.
    pub fn of(frame: Convention) -> Self {
        Page { frame }
    }

    fn sae(self) -> bool {
        self.frame.mirrors()
    }

    /// How far the fixed (natural) frame is turned on the page, degrees counter-clockwise: 0 for
    /// the natural frame, 90 for SAE (x up).
    pub fn turn_degrees(self) -> f64 {
        if self.sae() {
            90.0
        } else {
            0.0
        }
    }

    /// A point (or vector) of the fixed natural frame, in any length unit, on the page: to the
    /// right, up.
    pub fn point(self, p: [f64; 2]) -> [f64; 2] {
        self.frame.to_page(p)
    }

    /// [`Page::point`] of a tuple.
    pub fn xy(self, (x, y): (f64, f64)) -> (f64, f64) {
        let [h, v] = self.point([x, y]);
        (h, v)
    }

    /// The label of the page's horizontal axis (`len`: the length unit's label).
    pub fn horizontal_label(self, len: &str) -> String {
        if self.sae() {
            format!("y [{len}] (SAE: to the right of x)")
        } else {
            format!("x [{len}]")
        }
    }

    /// The label of the page's vertical axis.
    pub fn vertical_label(self, len: &str) -> String {
        if self.sae() {
            format!("x [{len}] (SAE)")
        } else {
            format!("y [{len}]")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sae_points_lie_as_on_a_map() {
        let page = Page::of(Convention::Sae);
        // An SAE point 30 ft east (y = +30) and 10 ft north (x = 10) is (10, -30) in the natural
        // frame; on the page it is 30 to the right and 10 up.
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-12;
        assert!(close(page.point([10.0, -30.0]), [30.0, 10.0]));
        // A rotation, not a reflection: the orientation of a triangle is kept.
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]].map(|p| page.point(p));
        let cross = (tri[1][0] - tri[0][0]) * (tri[2][1] - tri[0][1])
            - (tri[1][1] - tri[0][1]) * (tri[2][0] - tri[0][0]);
        assert!(cross > 0.0);
        assert!(close(
            Page::of(Convention::Natural).point([10.0, -30.0]),
            [10.0, -30.0]
        ));
    }
}
