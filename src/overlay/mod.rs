//! 2D drawings with tiny-skia: the CIE chromaticity diagram, HUD and plots.
