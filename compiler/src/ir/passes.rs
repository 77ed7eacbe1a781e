//! IR passes.

use super::Function;

/// Runs the passes that pay.
pub fn optimize(_function: &mut Function) {}
