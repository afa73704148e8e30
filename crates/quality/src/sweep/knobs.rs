//! The knobs: one setting of them and its label, and the settings each subject sweeps
//! (one knob at a time around a base setting).

use super::*;

/// One setting of the knobs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Setting {
    /// Tessellation of an analytic shape (0 when the scene is fixed).
    pub slices: u32,
    pub stacks: u32,
    pub shading: Shading,
    /// Supersampling factor per axis.
    pub ss: u32,
    /// Multisampling: coverage and depth samples per pixel (1 or 4).
    pub msaa: u32,
    /// Texture filter forced on every texture (`None`: each texture's own).
    pub filter: Option<Filter>,
    /// Sub-pixel bits of the rasterizer's vertex snap.
    pub bits: u8,
    /// Shadow map texels per side and PCF radius (0, 0: the settings' own).
    pub shadow_size: u32,
    pub pcf: u32,
    /// Measured against the path tracer's every bounce instead of its direct light
    /// ([`Subject::Traced`] only).
    pub global: bool,
}

impl Default for Setting {
    /// Phong, one sample, the texture's own filter, full sub-pixel precision, the
    /// settings' shadows, no tessellation (a fixed scene).
    fn default() -> Self {
        Self {
            slices: 0,
            stacks: 0,
            shading: Shading::Phong,
            ss: 1,
            msaa: 1,
            filter: None,
            bits: SUBPIXEL_BITS as u8,
            shadow_size: 0,
            pcf: 0,
            global: false,
        }
    }
}

impl Setting {
    /// A short label, e.g. "phong 64x32 ss2", "textured bilinear ss1" or "phong 64x32 ss1
    /// msaa4".
    #[must_use]
    pub fn label(&self) -> String {
        let mut out = self.shading.to_string();
        if self.shading == Shading::Path {
            // The path tracer's samples are paths per pixel, not supersampling.
            out.push_str(&format!(" {}spp", self.ss * self.ss));
            if self.global {
                out.push_str(" global");
            }
            return out;
        }
        if self.shadow_size > 0 {
            out.push_str(&format!(" shadow{}", self.shadow_size));
        }
        if self.shadow_size > 0 || self.pcf > 0 {
            out.push_str(&format!(" pcf{}", self.pcf));
        }
        if self.slices > 0 {
            out.push_str(&format!(" {}x{}", self.slices, self.stacks));
        }
        if let Some(f) = self.filter {
            out.push(' ');
            out.push_str(filter_name(f));
        }
        out.push_str(&format!(" ss{}", self.ss));
        if self.msaa > 1 {
            out.push_str(&format!(" msaa{}", self.msaa));
        }
        if u32::from(self.bits) != SUBPIXEL_BITS {
            out.push_str(&format!(" {}bit", self.bits));
        }
        if self.global {
            out.push_str(" global");
        }
        out
    }
}

/// A texture filter's name in labels and `results.csv` ([`Filter::name`]).
#[must_use]
pub fn filter_name(f: Filter) -> &'static str {
    f.name()
}

/// The traced scenes' settings, `pbr` with the default shadow map (1,024 texels, PCF
/// radius 1) as the base. Under the shadow-casting light: the shadow map's size and
/// filter, supersampling, and `whitted`'s traced shadows; under the environment: `pbr`'s
/// unoccluded environment light. Then the path tracer at 1, 4 and 16 paths a pixel, all
/// against the direct light; and the base, `whitted` and 16 paths against every bounce.
pub(super) fn traced_settings(light: Light) -> Vec<(&'static str, Setting)> {
    let base = Setting {
        shading: Shading::Pbr,
        shadow_size: crate::shade::SHADOW_SIZE,
        pcf: 1,
        ..Setting::default()
    };
    let mut out = Vec::new();
    match light {
        Light::Shadows => {
            for shadow_size in [256, 512, 1024, 2048, 4096, 8192] {
                out.push((
                    "shadow map",
                    Setting {
                        shadow_size,
                        ..base
                    },
                ));
            }
            for pcf in [0, 1, 2, 4] {
                out.push(("shadow filter", Setting { pcf, ..base }));
            }
            out.push(("supersampling", Setting { ss: 2, ..base }));
            let traced = Setting {
                shading: Shading::Whitted,
                shadow_size: 0,
                pcf: 0,
                ..base
            };
            out.push(("traced shadows", traced));
            out.push(("traced shadows", Setting { ss: 2, ..traced }));
        }
        Light::Environment => {
            // No light casts shadows here.
            let base = Setting {
                shadow_size: 0,
                pcf: 0,
                ..base
            };
            out.push(("environment", base));
            out.push(("environment", Setting { ss: 2, ..base }));
        }
    }
    let path = Setting {
        shading: Shading::Path,
        shadow_size: 0,
        pcf: 0,
        ..base
    };
    for ss in [1, 2, 4] {
        out.push(("path", Setting { ss, ..path }));
    }
    let shadowed = light == Light::Shadows;
    out.push((
        "global",
        Setting {
            global: true,
            shadow_size: if shadowed { base.shadow_size } else { 0 },
            pcf: if shadowed { base.pcf } else { 0 },
            ..base
        },
    ));
    if shadowed {
        out.push((
            "global",
            Setting {
                shading: Shading::Whitted,
                shadow_size: 0,
                pcf: 0,
                global: true,
                ..base
            },
        ));
    }
    out.push((
        "global",
        Setting {
            ss: 4,
            global: true,
            ..path
        },
    ));
    out
}

/// A model's settings around a base setting: on an untextured model every lit shading
/// mode (Phong is the base); on a textured one the texture filters (the textured mode is
/// the base: the other modes draw no texture, so they are not approximations of the same
/// image); then supersampling and sub-pixel bits.
pub(super) fn model_settings(textured: bool) -> Vec<(&'static str, Setting)> {
    let base = Setting {
        slices: 0,
        stacks: 0,
        shading: if textured {
            Shading::Textured
        } else {
            Shading::Phong
        },
        ..Setting::default()
    };
    let mut out = Vec::new();
    if textured {
        for filter in Filter::COMMON {
            out.push((
                "filter",
                Setting {
                    filter: Some(filter),
                    ..base
                },
            ));
        }
    } else {
        for shading in LIT_MODES {
            out.push(("shading", Setting { shading, ..base }));
        }
    }
    for ss in [1, 2, 4] {
        out.push(("supersampling", Setting { ss, ..base }));
    }
    out.push(("multisampling", Setting { msaa: 4, ..base }));
    for bits in [0u8, 2, 4, 8] {
        out.push(("sub-pixel bits", Setting { bits, ..base }));
    }
    out
}

/// The untextured lit modes the shading knob compares.
const LIT_MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Blinn,
];

/// The plane's settings: every texture filter ([`Filter::COMMON`]: nearest, bilinear,
/// trilinear, aniso:2/4/8/16), the first three also with 2x2 and 4x4 supersampling.
pub(super) fn plane_settings() -> Vec<(&'static str, Setting)> {
    let mut out = Vec::new();
    for filter in Filter::COMMON {
        let supersampled: &[u32] = if matches!(filter, Filter::Anisotropic(_)) {
            &[1]
        } else {
            &[1, 2, 4]
        };
        for &ss in supersampled {
            let knob = if ss == 1 { "filter" } else { "supersampling" };
            out.push((
                knob,
                Setting {
                    shading: Shading::Textured,
                    ss,
                    filter: Some(filter),
                    ..Setting::default()
                },
            ));
        }
    }
    out
}

/// The sphere's and cylinder's settings: the base (Phong, 64 slices, no supersampling) and
/// one knob at a time around it, and around a fine base (256 slices). Stacks are half the
/// slices for the sphere; the cylinder has none (1).
#[must_use]
pub fn shape_settings(shape: Shape) -> Vec<(&'static str, Setting)> {
    let stacks = |slices: u32| {
        if shape == Shape::Sphere {
            slices / 2
        } else {
            1
        }
    };
    let base = Setting {
        slices: 64,
        stacks: stacks(64),
        shading: Shading::Phong,
        ..Setting::default()
    };
    let fine = Setting {
        slices: 256,
        stacks: stacks(256),
        ..base
    };
    let mut out = Vec::new();
    for slices in [8, 16, 32, 64, 128, 256, 512] {
        out.push((
            "tessellation",
            Setting {
                slices,
                stacks: stacks(slices),
                ..base
            },
        ));
    }
    for shading in LIT_MODES {
        out.push(("shading", Setting { shading, ..base }));
        out.push(("shading", Setting { shading, ..fine }));
    }
    for ss in [1, 2, 4] {
        out.push(("supersampling", Setting { ss, ..base }));
        out.push(("supersampling", Setting { ss, ..fine }));
    }
    for msaa in [1, 4] {
        out.push(("multisampling", Setting { msaa, ..base }));
        out.push(("multisampling", Setting { msaa, ..fine }));
    }
    for bits in [0u8, 2, 4, 6, 8] {
        out.push(("sub-pixel bits", Setting { bits, ..fine }));
    }
    out
}
