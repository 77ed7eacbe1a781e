//! Code generation: the IR of a program to machine code with Cranelift, in
//! memory (`jit`) or as an object file (`object`). Both go through
//! `define_program`, so they run the same code.

mod divide;
mod jit;
mod near;
mod object;
mod translate;
mod wide;

pub use jit::JitProgram;
pub use object::{emit_object, ObjectOptions, DEFAULT_PREFIX};

use cranelift_codegen::ir::{types, AbiParam, InstBuilder, Signature, StackSlotData, StackSlotKind, UserFuncName};
use cranelift_codegen::isa::{OwnedTargetIsa, TargetIsa};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_module::{FuncId, Linkage, Module, ModuleError};
use ladder_ir::{Function, Program};
use ladder_runtime::helpers::Helper;
use ladder_runtime::layout::Layout;
use std::sync::atomic::{AtomicUsize, Ordering};
use translate::{translate, Locals};

/// Something went wrong in the back end. Not expected for any checked
/// program; reported rather than panicking.
#[derive(Debug, thiserror::Error)]
pub enum CodegenError {
    #[error(
        "unsupported target `{0}`: ladderc builds object files for x86_64-unknown-linux-gnu, \
         aarch64-unknown-linux-gnu and riscv64gc-unknown-linux-gnu (and the same CPUs on other systems), and \
         through its C back end for thumbv6m-none-eabi, thumbv7m-none-eabi, thumbv7em-none-eabi, thumbv7em-none-eabihf, \
         armv7-unknown-linux-gnueabihf and riscv32imac-unknown-none-elf; `--emit c` writes portable C for \
         any other"
    )]
    Target(String),
    #[error("this machine is not a target ladderc can compile for: {0}")]
    HostTarget(String),
    #[error("code generation failed: {0}")]
    Module(String),
    #[error("cannot write the object file: {0}")]
    Object(String),
}

impl From<ModuleError> for CodegenError {
    fn from(error: ModuleError) -> Self {
        CodegenError::Module(format!("{error:?}"))
    }
}

/// Cranelift flags for ladderc: optimise for speed, verify the generated IR
/// in debug builds (and so in every test).
fn flags(pic: bool) -> settings::Flags {
    let mut builder = settings::builder();
    let set = |builder: &mut settings::Builder, name: &str, value: &str| {
        builder.set(name, value).expect("a setting every Cranelift build knows");
    };
    // Our IR arrives optimised (constants folded, memory forwarded, dead
    // values gone); Cranelift's own rewriting (e-graphs) would move every
    // load of a rung ahead of the logic that uses it, which keeps x86 from
    // taking the loads as memory operands (`wide.rs`). Measured on the
    // benchmarks' bit logic and mixed plant: faster without it, and builds
    // take less time.
    set(&mut builder, "opt_level", "none");
    set(
        &mut builder,
        "enable_verifier",
        if cfg!(debug_assertions) { "true" } else { "false" },
    );
    set(&mut builder, "is_pic", if pic { "true" } else { "false" });
    set(&mut builder, "use_colocated_libcalls", "false");
    settings::Flags::new(builder)
}

/// The ISA for a target triple (`None`: the host).
fn target_isa(triple: Option<&str>, pic: bool) -> Result<OwnedTargetIsa, CodegenError> {
    let builder = match triple {
        None => cranelift_native::builder().map_err(|e| CodegenError::HostTarget(e.to_string()))?,
        Some(name) => {
            let triple: target_lexicon::Triple = name.parse().map_err(|_| CodegenError::Target(name.to_string()))?;
            cranelift_codegen::isa::lookup(triple).map_err(|_| CodegenError::Target(name.to_string()))?
        }
    };
    builder
        .finish(flags(pic))
        .map_err(|e| CodegenError::HostTarget(e.to_string()))
}

/// A C signature. On riscv64, 32-bit arguments are sign-extended by the
/// caller: its psABI requires it (for unsigned ones too) and callees
/// compiled by LLVM rely on it. Elsewhere the callee ignores the upper bits,
/// and extending them would cost an instruction per argument of every
/// helper call.
fn signature(isa: &dyn TargetIsa, params: &[types::Type]) -> Signature {
    let extend = matches!(isa.triple().architecture, target_lexicon::Architecture::Riscv64(_));
    let mut signature = Signature::new(isa.default_call_conv());
    signature.params.extend(params.iter().map(|&ty| {
        let param = AbiParam::new(ty);
        if ty == types::I32 && extend {
            param.sext()
        } else {
            param
        }
    }));
    signature
}

/// The C signature of a runtime helper: the image pointer, then its
/// declared parameters (all 32-bit).
fn helper_signature(isa: &dyn TargetIsa, pointer: types::Type, helper: Helper) -> Signature {
    let decl = helper.decl();
    let params: Vec<types::Type> = std::iter::once(pointer)
        .chain(decl.params.iter().map(|_| types::I32))
        .collect();
    let mut signature = signature(isa, &params);
    if decl.returns.is_some() {
        signature.returns.push(AbiParam::new(types::I32));
    }
    signature
}

/// Declares every runtime helper as an import of the module, in
/// `Helper::ALL` order.
fn declare_helpers(module: &mut dyn Module) -> Result<Vec<FuncId>, CodegenError> {
    let pointer = module.target_config().pointer_type();
    Helper::ALL
        .iter()
        .map(|&helper| {
            let signature = helper_signature(module.isa(), pointer, helper);
            Ok(module.declare_function(helper.decl().name, Linkage::Import, &signature)?)
        })
        .collect()
}

/// Whether an object for `isa` calls the runtime directly (`call rel32`,
/// bound by the linker like a C compiler's calls) rather than through the
/// global offset table: on x86-64, where the runtime is linked into the
/// same executable or library.
fn direct_calls(isa: &dyn TargetIsa) -> bool {
    isa.triple().architecture == target_lexicon::Architecture::X86_64
}

/// IR instructions per compiled function (see `translate::chunks`).
static CHUNK_INSTRUCTIONS: AtomicUsize = AtomicUsize::new(20_000);

/// Sets how many IR instructions a compiled function holds before the
/// program is cut into more functions, for this process. Tests make it small
/// so that ordinary programs take the multi-function path.
pub fn set_chunk_instructions(instructions: usize) {
    CHUNK_INSTRUCTIONS.store(instructions.max(1), Ordering::Relaxed);
}

/// Defines the program body `fn(mem)` in `module` under `name`, and each
/// subroutine as a local function `{name}.subN` of the same signature that
/// the body and other subroutines call, for an image with `layout`.
/// With `direct_calls`, helpers are called directly (`call rel32`), as the
/// object is linked with the runtime (JIT code may lie too far from the
/// runtime's code for that).
fn define_program(
    module: &mut dyn Module,
    layout: &Layout,
    program: &Program,
    name: &str,
    linkage: Linkage,
    direct_calls: bool,
) -> Result<FuncId, CodegenError> {
    let helpers = declare_helpers(module)?;
    let pointer = module.target_config().pointer_type();
    let body_signature = signature(module.isa(), &[pointer]);
    let id = module.declare_function(name, linkage, &body_signature)?;
    let mut subroutines = Vec::with_capacity(program.subroutines.len());
    for number in 0..program.subroutines.len() {
        subroutines.push(module.declare_function(&format!("{name}.sub{number}"), Linkage::Local, &body_signature)?);
    }
    let mut builder_context = FunctionBuilderContext::new();
    let mut define = |module: &mut dyn Module, function: &Function, id: FuncId, name: &str| {
        let mut values = vec![None; function.value_types.len()];
        let mut part = Part {
            layout,
            direct_calls,
            wide_bits: module.isa().triple().architecture == target_lexicon::Architecture::X86_64,
            program: function,
            helpers: &helpers,
            subroutines: &subroutines,
            pointer,
            values: &mut values,
            builder_context: &mut builder_context,
        };
        part.define_whole(module, id, name, body_signature.clone())
    };
    define(module, &program.main, id, name)?;
    for (number, (function, &sub_id)) in program.subroutines.iter().zip(&subroutines).enumerate() {
        define(module, function, sub_id, &format!("{name}.sub{number}"))?;
    }
    Ok(id)
}

/// What translating one function of a program needs.
struct Part<'a> {
    layout: &'a Layout,
    /// Helpers are called directly (`define_program`).
    direct_calls: bool,
    /// Bits are wide (`wide.rs`): on x86-64.
    wide_bits: bool,
    program: &'a Function,
    helpers: &'a [FuncId],
    subroutines: &'a [FuncId],
    pointer: types::Type,
    values: &'a mut Vec<Option<cranelift_codegen::ir::Value>>,
    builder_context: &'a mut FunctionBuilderContext,
}

impl Part<'_> {
    /// Defines `fn(mem)` `id` from the whole function: one Cranelift
    /// function, or for a large one a function that calls its chunks in
    /// order with the locals (master-control powers, loop counts) in a
    /// stack slot.
    fn define_whole(
        &mut self,
        module: &mut dyn Module,
        id: FuncId,
        name: &str,
        body_signature: Signature,
    ) -> Result<(), CodegenError> {
        let function = self.program;
        let pointer = self.pointer;
        let chunks = translate::chunks(function, CHUNK_INSTRUCTIONS.load(Ordering::Relaxed));
        if let [whole] = chunks.as_slice() {
            return self.define(module, id, body_signature, whole.clone(), Locals::Variables);
        }
        let chunk_signature = signature(module.isa(), &[pointer, pointer]);
        let mut chunk_ids = Vec::with_capacity(chunks.len());
        for (number, range) in chunks.iter().enumerate() {
            let chunk_id =
                module.declare_function(&format!("{name}.part{number}"), Linkage::Local, &chunk_signature)?;
            self.define(module, chunk_id, chunk_signature.clone(), range.clone(), Locals::Memory)?;
            chunk_ids.push(chunk_id);
        }
        let mut context = module.make_context();
        context.func.signature = body_signature;
        context.func.name = UserFuncName::user(0, id.as_u32());
        let mut builder = FunctionBuilder::new(&mut context.func, self.builder_context);
        let entry = builder.create_block();
        builder.append_block_params_for_function_params(entry);
        builder.switch_to_block(entry);
        let mem = builder.block_params(entry)[0];
        let size = translate::locals_size(function);
        let slot = builder.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, size.max(4), 2));
        let zero = builder.ins().iconst(types::I8, 0);
        for offset in 0..size as i32 {
            builder.ins().stack_store(pointer, zero, slot, offset);
        }
        let locals = builder.ins().stack_addr(pointer, slot, 0);
        for &chunk_id in &chunk_ids {
            let callee = module.declare_func_in_func(chunk_id, builder.func);
            builder.ins().call(callee, &[mem, locals]);
        }
        builder.ins().return_(&[]);
        builder.seal_all_blocks();
        builder.finalize(module.target_config());
        module.define_function(id, &mut context)?;
        Ok(())
    }

    /// Defines function `id` from the program's blocks `range`.
    fn define(
        &mut self,
        module: &mut dyn Module,
        id: FuncId,
        signature: Signature,
        range: std::ops::Range<usize>,
        locals: Locals,
    ) -> Result<(), CodegenError> {
        let mut context = module.make_context();
        context.func.signature = signature;
        context.func.name = UserFuncName::user(0, id.as_u32());
        let mut builder = FunctionBuilder::new(&mut context.func, self.builder_context);
        let refs: Vec<_> = self
            .helpers
            .iter()
            .map(|&helper| {
                let reference = module.declare_func_in_func(helper, builder.func);
                builder.func.dfg.ext_funcs[reference].colocated = self.direct_calls;
                reference
            })
            .collect();
        let subroutines: Vec<_> = self
            .subroutines
            .iter()
            .map(|&subroutine| module.declare_func_in_func(subroutine, builder.func))
            .collect();
        translate(
            self.layout,
            self.program,
            range,
            locals,
            &mut builder,
            &refs,
            &subroutines,
            self.pointer,
            self.values,
            self.wide_bits,
        );
        builder.finalize(module.target_config());
        module.define_function(id, &mut context)?;
        Ok(())
    }
}
