//! The object-file back end: the program and its C-ABI scan entry point.

use super::{define_program, signature, target_isa, CodegenError};
use crate::ir::Program;
use cranelift_codegen::ir::{types, InstBuilder, UserFuncName};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_module::{default_libcall_names, Linkage, Module};
use cranelift_object::{ObjectBuilder, ObjectModule};

/// What `ladderc build` asks of the object back end.
#[derive(Clone, Debug, Default)]
pub struct ObjectOptions {
    /// Target triple; `None` for the host.
    pub target: Option<String>,
    /// Prefix of the exported entry point `<prefix>scan`.
    pub prefix: String,
}

/// The default prefix: the entry point is `ladder_program_scan`.
pub const DEFAULT_PREFIX: &str = "ladder_program_";

/// Compiles the program into an object file exporting
/// `void <prefix>scan(LadderMemory *mem, uint32_t elapsed_ms)`, which runs one
/// whole scan (a null `mem` does nothing) (it calls the runtime's layout-tagged begin-scan and
/// `ladder_end_scan`, so it only links against a runtime with its layout).
pub fn emit_object(program: &Program, options: &ObjectOptions) -> Result<Vec<u8>, CodegenError> {
    let isa = target_isa(options.target.as_deref(), true)?;
    let builder = ObjectBuilder::new(isa, "ladder_program", default_libcall_names())?;
    let mut module = ObjectModule::new(builder);
    let body = define_program(&mut module, program, &format!("{}body", options.prefix), Linkage::Local)?;

    let pointer = module.target_config().pointer_type();
    let scan_signature = signature(module.isa(), &[pointer, types::I32]);
    let end_signature = signature(module.isa(), &[pointer]);
    let begin = module.declare_function(
        ladder_runtime::layout::TAGGED_BEGIN_SCAN,
        Linkage::Import,
        &scan_signature,
    )?;
    let end = module.declare_function(ladder_runtime::layout::END_SCAN, Linkage::Import, &end_signature)?;
    let entry = module.declare_function(&format!("{}scan", options.prefix), Linkage::Export, &scan_signature)?;

    let mut context = module.make_context();
    context.func.signature = scan_signature;
    context.func.name = UserFuncName::user(0, entry.as_u32());
    let mut builder_context = FunctionBuilderContext::new();
    {
        let mut builder = FunctionBuilder::new(&mut context.func, &mut builder_context);
        let block = builder.create_block();
        let scan = builder.create_block();
        let done = builder.create_block();
        builder.append_block_params_for_function_params(block);
        builder.switch_to_block(block);
        let (mem, elapsed) = (builder.block_params(block)[0], builder.block_params(block)[1]);
        // A null image is ignored, as by every function of the C API.
        builder.ins().brif(mem, scan, &[], done, &[]);
        builder.switch_to_block(scan);
        let begin = module.declare_func_in_func(begin, builder.func);
        let body = module.declare_func_in_func(body, builder.func);
        let end = module.declare_func_in_func(end, builder.func);
        builder.ins().call(begin, &[mem, elapsed]);
        builder.ins().call(body, &[mem]);
        builder.ins().call(end, &[mem]);
        builder.ins().jump(done, &[]);
        builder.switch_to_block(done);
        builder.ins().return_(&[]);
        builder.seal_all_blocks();
        builder.finalize(module.target_config());
    }
    module.define_function(entry, &mut context)?;
    module.finish().emit().map_err(|e| CodegenError::Object(e.to_string()))
}
