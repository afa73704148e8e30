//! Primitive builders.
