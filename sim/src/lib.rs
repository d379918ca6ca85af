//! 2D discrete-element engine for spheropolygons.
