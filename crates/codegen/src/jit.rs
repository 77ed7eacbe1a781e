//! The JIT back end: the program compiled into this process.

use super::{define_program, target_isa, CodegenError};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, Linkage};
use ladder_ir::Program;
use ladder_runtime::Memory;

/// A program compiled to machine code in memory.
pub struct JitProgram {
    /// Owns the code; freed on drop.
    module: Option<JITModule>,
    body: unsafe extern "C" fn(*mut Memory),
}

impl JitProgram {
    pub fn compile(program: &Program) -> Result<JitProgram, CodegenError> {
        let isa = target_isa(None, false)?;
        let mut builder = JITBuilder::with_isa(isa, default_libcall_names());
        for (name, address) in ladder_runtime::helpers::symbols() {
            builder.symbol(name, address);
        }
        let mut module = JITModule::new(builder);
        // The JIT runs programs on `Memory`: the full layout.
        let id = define_program(
            &mut module,
            &ladder_runtime::layout::FULL,
            program,
            "ladder_program",
            Linkage::Local,
            false,
        )?;
        module.finalize_definitions()?;
        let code = module.get_finalized_function(id);
        // SAFETY: `code` is the function just defined with the signature
        // `fn(*mut Memory)` in the host's default calling convention, which is
        // the C convention of this process.
        let body = unsafe { std::mem::transmute::<*const u8, unsafe extern "C" fn(*mut Memory)>(code) };
        Ok(JitProgram {
            module: Some(module),
            body,
        })
    }

    /// Step 3 of the scan on `mem`.
    pub fn run(&self, mem: &mut Memory) {
        // SAFETY: the code only touches the image it is given, within its
        // bounds (indices are clamped in generated code), and calls runtime
        // helpers with it.
        unsafe { (self.body)(mem) }
    }
}

impl Drop for JitProgram {
    fn drop(&mut self) {
        if let Some(module) = self.module.take() {
            // SAFETY: `body` points into this module and is not used after drop.
            unsafe { module.free_memory() };
        }
    }
}
