//! G-code reader and writers.
