//! Constructive solid geometry of straight and circular edges (to be written: issue 2).
