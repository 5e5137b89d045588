//! Chromatic adaptation transforms: von Kries scaling of cone-like responses.

use super::Mat3;
use crate::error::ColorError;

/// Which cone-response space the von Kries scaling happens in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cat {
    /// Bradford (Lam 1985, linearised as in ICC and CIE 159 practice).
    Bradford,
    /// CAT02 of CIECAM02 (CIE 159:2004).
    Cat02,
    /// Von Kries with the Hunt–Pointer–Estévez cone fundamentals
    /// (normalised to equal-energy white).
    VonKries,
}

impl Cat {
    /// XYZ → cone-like response.
    pub fn matrix(self) -> Mat3 {
        match self {
            // Lam 1985 (the "Bradford" transform, linear part).
            Cat::Bradford => Mat3([
                [0.8951, 0.2664, -0.1614],
                [-0.7502, 1.7135, 0.0367],
                [0.0389, -0.0685, 1.0296],
            ]),
            // CIE 159:2004, M_CAT02.
            Cat::Cat02 => Mat3([
                [0.7328, 0.4296, -0.1624],
                [-0.7036, 1.6975, 0.0061],
                [0.0030, 0.0136, 0.9834],
            ]),
            // Hunt–Pointer–Estévez, equal-energy normalised (Fairchild, Color
            // Appearance Models, 3rd ed., eq. 9.8).
            Cat::VonKries => Mat3([
                [0.40024, 0.70760, -0.08081],
                [-0.22630, 1.16532, 0.04570],
                [0.0, 0.0, 0.91822],
            ]),
        }
    }

    pub fn from_name(name: &str) -> Result<Self, ColorError> {
        match name
            .to_ascii_lowercase()
            .replace(['-', '_', ' '], "")
            .as_str()
        {
            "bradford" => Ok(Cat::Bradford),
            "cat02" => Ok(Cat::Cat02),
            "vonkries" => Ok(Cat::VonKries),
            _ => Err(ColorError::UnknownName {
                what: "chromatic adaptation transform",
                name: name.into(),
                known: "bradford, cat02, vonkries".into(),
            }),
        }
    }
}

/// The XYZ → XYZ matrix that adapts colours seen under white `src` to how
/// they appear under white `dst` (whites as XYZ): M⁻¹·diag(M·dst / M·src)·M.
pub fn adaptation_matrix(src: [f64; 3], dst: [f64; 3], cat: Cat) -> Mat3 {
    let m = cat.matrix();
    let (s, d) = (m.apply(src), m.apply(dst));
    // The three transforms are invertible (constant matrices, checked by test).
    m.inverse().expect("CAT matrix invertible")
        * Mat3::diagonal([d[0] / s[0], d[1] / s[1], d[2] / s[2]])
        * m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::rgb::xy_to_xyz;

    #[test]
    fn whites_map_to_whites() {
        let d65 = xy_to_xyz([0.3127, 0.3290]);
        let a = xy_to_xyz([0.44757, 0.40745]);
        for cat in [Cat::Bradford, Cat::Cat02, Cat::VonKries] {
            assert!(cat.matrix().inverse().is_some());
            let m = adaptation_matrix(a, d65, cat);
            let w = m.apply(a);
            for k in 0..3 {
                assert!((w[k] - d65[k]).abs() < 1e-12, "{cat:?}");
            }
        }
        assert_eq!(Cat::from_name("Von-Kries").unwrap(), Cat::VonKries);
        assert!(Cat::from_name("xyz").is_err());
    }
}
