//! Synthetic photographs and grain detection.
