//! The stages after the checker, in order: lowering to IR, IR passes, and
//! code generation.

use crate::codegen::{emit_object, CodegenError, JitProgram, ObjectOptions};
use crate::ir::{passes, Program};
use crate::program::CheckedProgram;

/// The optimised IR of a checked program.
pub fn ir(program: &CheckedProgram) -> Program {
    let mut ir = crate::lower::lower(program);
    passes::optimize(&mut ir);
    ir
}

/// The program compiled into this process.
pub fn jit(program: &CheckedProgram) -> Result<JitProgram, CodegenError> {
    JitProgram::compile(&ir(program))
}

/// The program as an object file.
pub fn object(program: &CheckedProgram, options: &ObjectOptions) -> Result<Vec<u8>, CodegenError> {
    emit_object(&ir(program), options)
}

/// The program as portable C (the C back end, from the same optimised IR).
pub fn c_source(program: &CheckedProgram, options: &crate::cback::COptions) -> String {
    crate::cback::emit_c(&ir(program), options)
}
