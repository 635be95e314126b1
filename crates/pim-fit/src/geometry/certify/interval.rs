//! Closed intervals of reals with outward rounding: every operation widens its result by one
//! unit in the last place on each side, which covers the rounding of the (correctly rounded)
//! floating-point operation; sine and cosine are widened by 4e-16 more (the platform's libm is
//! accurate to about one unit in the last place).

use std::ops::{Add, Mul, Neg, Sub};

/// `[lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Iv {
    pub lo: f64,
    pub hi: f64,
}

impl Iv {
    /// The interval `[lo, hi]` (no widening).
    pub fn new(lo: f64, hi: f64) -> Iv {
        debug_assert!(lo <= hi || lo.is_nan() || hi.is_nan());
        Iv { lo, hi }
    }

    /// The point `v`.
    pub fn point(v: f64) -> Iv {
        Iv { lo: v, hi: v }
    }

    /// The whole line.
    pub fn entire() -> Iv {
        Iv {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        }
    }

    fn out(lo: f64, hi: f64) -> Iv {
        if lo.is_nan() || hi.is_nan() {
            return Iv::entire();
        }
        Iv {
            lo: -next_up(-lo),
            hi: next_up(hi),
        }
    }

    /// The largest absolute value.
    pub fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// The midpoint.
    pub fn mid(self) -> f64 {
        0.5 * (self.lo + self.hi)
    }

    /// Whether every value is above zero, below zero (`Some(+1)`, `Some(-1)`), or neither.
    pub fn sign(self) -> Option<f64> {
        if self.lo > 0.0 {
            Some(1.0)
        } else if self.hi < 0.0 {
            Some(-1.0)
        } else {
            None
        }
    }

    /// `self * k` for a real k.
    pub fn scale(self, k: f64) -> Iv {
        let (a, b) = (self.lo * k, self.hi * k);
        Iv::out(a.min(b), a.max(b))
    }

    /// `self^2`.
    pub fn sqr(self) -> Iv {
        let (a, b) = (self.lo * self.lo, self.hi * self.hi);
        if self.lo <= 0.0 && self.hi >= 0.0 {
            Iv::out(0.0, a.max(b)).max0()
        } else {
            Iv::out(a.min(b), a.max(b)).max0()
        }
    }

    fn max0(self) -> Iv {
        Iv {
            lo: self.lo.max(0.0),
            hi: self.hi,
        }
    }

    /// `self / other`; the whole line when other contains zero.
    pub fn div(self, other: Iv) -> Iv {
        if other.lo <= 0.0 && other.hi >= 0.0 {
            return Iv::entire();
        }
        let c = [
            self.lo / other.lo,
            self.lo / other.hi,
            self.hi / other.lo,
            self.hi / other.hi,
        ];
        Iv::out(
            c.iter().copied().fold(f64::INFINITY, f64::min),
            c.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }

    /// Sine of an interval of radians.
    pub fn sin(self) -> Iv {
        (self - Iv::point(std::f64::consts::FRAC_PI_2)).cos()
    }

    /// Cosine of an interval of radians.
    pub fn cos(self) -> Iv {
        use std::f64::consts::PI;
        if !(self.lo.is_finite() && self.hi.is_finite()) || self.hi - self.lo >= 2.0 * PI {
            return Iv::new(-1.0, 1.0);
        }
        let (a, b) = (self.lo.cos(), self.hi.cos());
        let (mut lo, mut hi) = (a.min(b), a.max(b));
        // Maxima at 2k pi, minima at (2k + 1) pi inside the interval (rounded outward: a
        // multiple next to an end counts as inside).
        let first = (self.lo / PI).floor() as i64;
        let last = (self.hi / PI).ceil() as i64;
        for k in first..=last {
            let x = k as f64 * PI;
            if x >= self.lo - 1e-12 && x <= self.hi + 1e-12 {
                if k.rem_euclid(2) == 0 {
                    hi = 1.0;
                } else {
                    lo = -1.0;
                }
            }
        }
        Iv::new((lo - 4e-16).max(-1.0), (hi + 4e-16).min(1.0))
    }
}

/// The next representable number above x (x itself at infinity).
fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    f64::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

impl Add for Iv {
    type Output = Iv;
    fn add(self, o: Iv) -> Iv {
        Iv::out(self.lo + o.lo, self.hi + o.hi)
    }
}

impl Sub for Iv {
    type Output = Iv;
    fn sub(self, o: Iv) -> Iv {
        Iv::out(self.lo - o.hi, self.hi - o.lo)
    }
}

impl Neg for Iv {
    type Output = Iv;
    fn neg(self) -> Iv {
        Iv {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for Iv {
    type Output = Iv;
    fn mul(self, o: Iv) -> Iv {
        let c = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        // 0 * inf arises only from unbounded operands: the whole line.
        if c.iter().any(|v| v.is_nan()) {
            return Iv::entire();
        }
        Iv::out(
            c.iter().copied().fold(f64::INFINITY, f64::min),
            c.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contains(i: Iv, v: f64) -> bool {
        i.lo <= v && v <= i.hi
    }

    #[test]
    fn next_up_is_the_next_number() {
        for x in [1.0, -1.0, 0.0, -0.0, 1e-308, -1e300, 3.5] {
            let y = next_up(x);
            assert!(y > x && (y - x) <= f64::EPSILON * x.abs().max(f64::MIN_POSITIVE));
        }
    }

    #[test]
    fn operations_contain_every_pointwise_result() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 8.0 - 4.0
        };
        for _ in 0..2000 {
            let (a, b, c, d) = (next(), next(), next(), next());
            let x = Iv::new(a.min(b), a.max(b));
            let y = Iv::new(c.min(d), c.max(d));
            for _ in 0..5 {
                let t = 0.5 + 0.5 * next() / 4.0;
                let u = 0.5 + 0.5 * next() / 4.0;
                let (p, q) = (x.lo + t * (x.hi - x.lo), y.lo + u * (y.hi - y.lo));
                assert!(contains(x + y, p + q));
                assert!(contains(x - y, p - q));
                assert!(contains(x * y, p * q));
                assert!(contains(x.sqr(), p * p));
                assert!(contains(x.scale(-2.5), -2.5 * p));
                assert!(contains(x.cos(), p.cos()));
                assert!(contains(x.sin(), p.sin()));
                if y.sign().is_some() {
                    assert!(contains(x.div(y), p / q));
                }
            }
        }
        // The extrema of cosine inside an interval.
        let c = Iv::new(-0.1, 3.2).cos();
        assert!(c.lo <= -1.0 && c.hi >= 1.0);
        let s = Iv::new(1.0, 2.0).sin();
        assert!(s.hi >= 1.0);
        assert!(s.lo <= 1.0f64.sin() && s.lo > 0.84);
    }
}
