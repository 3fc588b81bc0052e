//! Unit tests of the pbrt-v4 loader: every directive, and malformed input with its line and
//! column.
