//! The object-file back end: the program and its C-ABI scan entry point.

use super::{define_program, direct_calls, signature, target_isa, CodegenError};
use cranelift_codegen::ir::{types, AbiParam, InstBuilder, UserFuncName};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_module::{default_libcall_names, DataDescription, DataId, Linkage, Module};
use cranelift_object::{ObjectBuilder, ObjectModule};
use ladder_ir::Program;
use ladder_runtime::layout::{Layout, FULL};
use ladder_runtime::MachineUse;

/// What `ladderc build` asks of the object back end.
#[derive(Clone, Debug, Default)]
pub struct ObjectOptions {
    /// Target triple; `None` for the host.
    pub target: Option<String>,
    /// Prefix of the exported entry points `<prefix>scan` and `<prefix>init`.
    pub prefix: String,
    /// The image's layout: `None` for the full layout, or a compact one
    /// (`image::compact_layout`), which the object defines as `<prefix>layout`.
    pub layout: Option<Layout>,
    /// The parts of the machine the scan keeps up to date
    /// (`image::machine_use`).
    pub machine: MachineUse,
}

/// The default prefix: the entry point is `ladder_program_scan`.
pub const DEFAULT_PREFIX: &str = "ladder_program_";

/// Compiles the program into an object file exporting
/// `void <prefix>scan(LadderMemory *mem, uint32_t elapsed_ms)`, which runs one
/// whole scan, and `LadderMemory *<prefix>init(void *storage, size_t size)`,
/// which initialises an image with the program's layout. The scan calls the
/// runtime's layout-tagged begin-scan with the program's layout table (null
/// for the full layout) and does nothing when the image has another one (or
/// is null), so it only links against a runtime with its layout rules and
/// only runs on an image of its layout.
pub fn emit_object(program: &Program, options: &ObjectOptions) -> Result<Vec<u8>, CodegenError> {
    let isa = target_isa(options.target.as_deref(), true)?;
    let builder = ObjectBuilder::new(isa, "ladder_program", default_libcall_names())?;
    let mut module = ObjectModule::new(builder);
    let layout = options.layout.as_ref().unwrap_or(&FULL);
    let direct = direct_calls(module.isa());
    let body = define_program(
        &mut module,
        layout,
        program,
        &format!("{}body", options.prefix),
        Linkage::Local,
        direct,
    )?;
    let table = match &options.layout {
        Some(layout) => {
            let id = module.declare_data(&format!("{}layout", options.prefix), Linkage::Export, false, false)?;
            let mut data = DataDescription::new();
            let bytes: Vec<u8> = layout.words().iter().flat_map(|word| word.to_ne_bytes()).collect();
            data.define(bytes.into_boxed_slice());
            data.set_align(4);
            module.define_data(id, &data)?;
            Some(id)
        }
        None => None,
    };

    let pointer = module.target_config().pointer_type();
    let begin_signature = {
        let mut signature = signature(module.isa(), &[pointer, types::I32, pointer, types::I32]);
        signature.returns.push(AbiParam::new(types::I32));
        signature
    };
    let scan_signature = signature(module.isa(), &[pointer, types::I32]);
    let end_signature = signature(module.isa(), &[pointer, types::I32]);
    let begin = module.declare_function(
        ladder_runtime::layout::TAGGED_BEGIN_SCAN,
        Linkage::Import,
        &begin_signature,
    )?;
    let end = module.declare_function(ladder_runtime::layout::TAGGED_END_SCAN, Linkage::Import, &end_signature)?;
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
        let table = match table {
            Some(id) => {
                let table = module.declare_data_in_func(id, builder.func);
                builder.ins().symbol_value(pointer, table)
            }
            None => builder.ins().iconst(pointer, 0),
        };
        let begin = module.declare_func_in_func(begin, builder.func);
        let body = module.declare_func_in_func(body, builder.func);
        let end = module.declare_func_in_func(end, builder.func);
        for runtime in [begin, end] {
            builder.func.dfg.ext_funcs[runtime].colocated = direct;
        }
        // A null image, or one of another layout, is refused by the
        // begin-scan and then left alone.
        let machine = builder.ins().iconst(types::I32, i64::from(options.machine.bits()));
        let call = builder.ins().call(begin, &[mem, elapsed, table, machine]);
        let accepted = builder.inst_results(call)[0];
        builder.ins().brif(accepted, scan, &[], done, &[]);
        builder.switch_to_block(scan);
        builder.ins().call(body, &[mem]);
        let machine = builder.ins().iconst(types::I32, i64::from(options.machine.bits()));
        builder.ins().call(end, &[mem, machine]);
        builder.ins().jump(done, &[]);
        builder.switch_to_block(done);
        builder.ins().return_(&[]);
        builder.seal_all_blocks();
        builder.finalize(module.target_config());
    }
    module.define_function(entry, &mut context)?;
    define_init(&mut module, &options.prefix, table)?;
    module.finish().emit().map_err(|e| CodegenError::Object(e.to_string()))
}

/// `LadderMemory *<prefix>init(void *storage, size_t size)`: the runtime's
/// `ladder_init` for the full layout, `ladder_init_layout` with the
/// program's table for a compact one.
fn define_init(module: &mut ObjectModule, prefix: &str, table: Option<DataId>) -> Result<(), CodegenError> {
    let pointer = module.target_config().pointer_type();
    let mut init_signature = signature(module.isa(), &[pointer, pointer]);
    init_signature.returns.push(AbiParam::new(pointer));
    let mut runtime_signature = init_signature.clone();
    if table.is_some() {
        runtime_signature.params.push(AbiParam::new(pointer));
    }
    let runtime_init = module.declare_function(
        if table.is_some() {
            "ladder_init_layout"
        } else {
            "ladder_init"
        },
        Linkage::Import,
        &runtime_signature,
    )?;
    let init = module.declare_function(&format!("{prefix}init"), Linkage::Export, &init_signature)?;
    let mut context = module.make_context();
    context.func.signature = init_signature;
    context.func.name = UserFuncName::user(0, init.as_u32());
    let mut builder_context = FunctionBuilderContext::new();
    {
        let mut builder = FunctionBuilder::new(&mut context.func, &mut builder_context);
        let block = builder.create_block();
        builder.append_block_params_for_function_params(block);
        builder.switch_to_block(block);
        let mut args = builder.block_params(block).to_vec();
        if let Some(id) = table {
            let table = module.declare_data_in_func(id, builder.func);
            args.push(builder.ins().symbol_value(pointer, table));
        }
        let runtime_init = module.declare_func_in_func(runtime_init, builder.func);
        let call = builder.ins().call(runtime_init, &args);
        let image = builder.inst_results(call)[0];
        builder.ins().return_(&[image]);
        builder.seal_all_blocks();
        builder.finalize(module.target_config());
    }
    module.define_function(init, &mut context)?;
    Ok(())
}
