//! Vertex normals averaged from facet normals (seed 000 §9.2.2: N_a = (N_1 + ... + N_k) / k),
//! with area and angle weighting and crease-angle splitting.

/// How adjacent facet normals are weighted when averaged at a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize)]
pub enum Weighting {
    /// The seed's plain average.
    Uniform,
    /// Weighted by facet area.
    Area,
    /// Weighted by the facet's corner angle at the vertex (Thürmer & Wüthrich); independent of
    /// how a surface is tessellated.
    #[default]
    Angle,
}

/// Options for averaged normals.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NormalOptions {
    pub weighting: Weighting,
    /// Facets whose normals differ by more than this many degrees do not share a vertex
    /// normal (the vertex is split); `None` = always average (the seed's behaviour).
    pub crease_degrees: Option<f32>,
}

impl Default for NormalOptions {
    fn default() -> Self {
        Self { weighting: Weighting::Angle, crease_degrees: Some(60.0) }
    }
}
