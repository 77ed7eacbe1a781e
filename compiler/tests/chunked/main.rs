//! Programs compiled in parts (`chunked.rs`). A binary of its own: the
//! part size is a process-wide setting of the code generator
//! (`ladder_codegen::set_chunk_instructions`), which would otherwise cut
//! the differential test's programs too.

#[path = "../common/mod.rs"]
mod common;

mod chunked;
