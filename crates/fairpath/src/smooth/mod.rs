//! Smoothing methods (filled in below).
