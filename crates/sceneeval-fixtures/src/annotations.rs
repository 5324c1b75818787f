//! Work in progress: annotation rows written by the fixtures program.
