//! ladderc
