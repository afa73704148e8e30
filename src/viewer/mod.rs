//! The interactive viewer's logic that needs no GUI toolkit, so it can be unit-tested:
//! camera navigation ([`navigate`]) and the files around the open model ([`files`]).
//! The egui/eframe front end (behind the `viewer` feature) wires these to the window.

pub mod files;
pub mod navigate;
