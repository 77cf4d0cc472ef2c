//! What CNC controllers do with the codes fairpath reads and writes, as pure
//! arithmetic (no I/O): so that a program can be read as a controller runs
//! it, and so that the deviation of what a controller will run for a block
//! fairpath is about to write can be measured before it is written.
//!
//! * [`linuxcnc`]: LinuxCNC's G5, G5.1 and G5.2/G5.3 splines: its knot
//!   vector, its NURBS evaluation and the biarcs its canon layer turns them
//!   into.

pub mod linuxcnc;

pub use crate::geom::Plane;
