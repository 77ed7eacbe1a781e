//! The mathematical functions of the floating-point instructions (DSIN,
//! DEXP, DLOG10, ...), computed once for every engine: in double precision
//! by `libm` (the same code on every host and target, with or without a
//! standard library), rounded to single precision. Domain checks (an
//! arcsine of 2, a logarithm of 0) are the instructions' business.

/// A function of one real number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum RealFunction {
    Sin = 0,
    Cos = 1,
    Tan = 2,
    Asin = 3,
    Acos = 4,
    Atan = 5,
    /// e^x.
    Exp = 6,
    /// The natural logarithm.
    Ln = 7,
    Log10 = 8,
}

impl RealFunction {
    pub const ALL: [RealFunction; 9] = [
        RealFunction::Sin,
        RealFunction::Cos,
        RealFunction::Tan,
        RealFunction::Asin,
        RealFunction::Acos,
        RealFunction::Atan,
        RealFunction::Exp,
        RealFunction::Ln,
        RealFunction::Log10,
    ];

    pub fn from_code(code: u32) -> Option<RealFunction> {
        RealFunction::ALL.into_iter().find(|&f| f as u32 == code)
    }

    /// The function of `x` in double precision.
    pub fn apply(self, x: f64) -> f64 {
        match self {
            RealFunction::Sin => libm::sin(x),
            RealFunction::Cos => libm::cos(x),
            RealFunction::Tan => libm::tan(x),
            RealFunction::Asin => libm::asin(x),
            RealFunction::Acos => libm::acos(x),
            RealFunction::Atan => libm::atan(x),
            RealFunction::Exp => libm::exp(x),
            RealFunction::Ln => libm::log(x),
            RealFunction::Log10 => libm::log10(x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_values_are_sane() {
        for f in RealFunction::ALL {
            assert_eq!(RealFunction::from_code(f as u32), Some(f));
        }
        assert_eq!(RealFunction::from_code(99), None);
        assert!((RealFunction::Sin.apply(core::f64::consts::FRAC_PI_2) - 1.0).abs() < 1e-15);
        assert_eq!(RealFunction::Log10.apply(1000.0), 3.0);
        assert_eq!(RealFunction::Exp.apply(0.0), 1.0);
    }
}
