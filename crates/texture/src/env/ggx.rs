//! The GGX pieces the prefilter and the LUT share, in f64. They are the renderer's own
//! ([`crate::microfacet`]), so the environment is filtered with the lobe that lights it.

use crate::microfacet;

/// α of perceptual roughness `r` ([`crate::microfacet::alpha`]: r², clamped away from 0).
pub(super) fn alpha(r: f64) -> f64 {
    microfacet::alpha::<f64>(r)
}

pub(super) use crate::microfacet::{hammersley, sample_h};

/// GGX `D` ([`crate::microfacet::ggx`]) for NH > 0, else 0.
pub(super) fn d(nh: f64, alpha: f64) -> f64 {
    if nh <= 0.0 {
        return 0.0;
    }
    microfacet::ggx::<f64>(nh, alpha)
}

/// Height-correlated Smith `Vis` ([`crate::microfacet::smith_vis`]), for NL, NV >= 0.
pub(super) fn vis(nl: f64, nv: f64, alpha: f64) -> f64 {
    microfacet::smith_vis::<f64>(nl, nv, alpha)
}
