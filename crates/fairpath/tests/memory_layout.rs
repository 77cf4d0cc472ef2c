//! How large a piece is: a long run is held as pieces (as read, smoothed,
//! read back), so their size is what a program of one long run costs in
//! memory (issue 19). Arcs and NURBS curves are boxed in [`Curve`] so that
//! a line, the common piece, does not take an arc's room.

#![cfg(target_pointer_width = "64")]

use fairpath::geom::{Arc, Curve, Line, Nurbs};
use fairpath::path::Piece;

#[test]
fn a_line_piece_takes_96_bytes() {
    // A line's two points (48 bytes) and the enum's tag.
    assert_eq!(core::mem::size_of::<Curve>(), 56);
    assert_eq!(core::mem::size_of::<Line>(), 48);
    // The curve, the rapid flag, two source lines and a feed.
    assert_eq!(core::mem::size_of::<Piece>(), 96);
    // What boxing saves: an arc inline would make every curve this large.
    assert!(core::mem::size_of::<Arc>() > 2 * core::mem::size_of::<Line>());
    assert!(core::mem::size_of::<Nurbs>() > core::mem::size_of::<Line>());
}
