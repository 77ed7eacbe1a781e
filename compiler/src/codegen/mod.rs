//! Code generation: the IR of a program to machine code with Cranelift, in
//! memory (`jit`) or as an object file (`object`). Both go through
//! `define_program`, so they run the same code.

mod jit;
mod object;
mod translate;

pub use jit::JitProgram;
pub use object::{emit_object, ObjectOptions, DEFAULT_PREFIX};

use crate::ir::Function;
use cranelift_codegen::ir::{types, AbiParam, Signature, UserFuncName};
use cranelift_codegen::isa::{OwnedTargetIsa, TargetIsa};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_module::{FuncId, Linkage, Module, ModuleError};
use translate::{translate, HelperRefs};

/// Something went wrong in the back end. Not expected for any checked
/// program; reported rather than panicking.
#[derive(Debug, thiserror::Error)]
pub enum CodegenError {
    #[error("unsupported target `{0}`")]
    Target(String),
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
    set(&mut builder, "opt_level", "speed");
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
        None => cranelift_native::builder().map_err(|e| CodegenError::Target(e.to_string()))?,
        Some(name) => {
            let triple: target_lexicon::Triple = name.parse().map_err(|_| CodegenError::Target(name.to_string()))?;
            cranelift_codegen::isa::lookup(triple).map_err(|_| CodegenError::Target(name.to_string()))?
        }
    };
    builder
        .finish(flags(pic))
        .map_err(|e| CodegenError::Target(e.to_string()))
}

/// Names of the runtime functions compiled code imports.
mod names {
    pub const TIMER_COIL: &str = "ladder_rt_timer_coil";
    pub const COUNTER_COIL: &str = "ladder_rt_counter_coil";
    pub const RESET_TIMER: &str = "ladder_rt_reset_timer";
    pub const RESET_COUNTER: &str = "ladder_rt_reset_counter";
    pub const SCHEDULE_STATE_OFF: &str = "ladder_rt_schedule_state_off";
    pub const BLOCK_MOVE: &str = "ladder_rt_block_move";
    pub const END_SCAN: &str = "ladder_end_scan";
}

/// A C signature. 32-bit arguments are sign-extended by the caller: the
/// riscv64 psABI requires it (for unsigned ones too) and callees compiled by
/// LLVM rely on it; elsewhere it is harmless.
fn signature(isa: &dyn TargetIsa, params: &[types::Type]) -> Signature {
    let mut signature = Signature::new(isa.default_call_conv());
    signature.params.extend(params.iter().map(|&ty| {
        let param = AbiParam::new(ty);
        if ty == types::I32 {
            param.sext()
        } else {
            param
        }
    }));
    signature
}

/// The runtime helpers, declared as imports of the module.
struct Helpers {
    timer_coil: FuncId,
    counter_coil: FuncId,
    reset_timer: FuncId,
    reset_counter: FuncId,
    schedule_state_off: FuncId,
    block_move: FuncId,
}

impl Helpers {
    fn declare(module: &mut dyn Module) -> Result<Helpers, CodegenError> {
        let pointer = module.target_config().pointer_type();
        let i32 = types::I32;
        let isa = module.isa();
        let coil = signature(isa, &[pointer, i32, i32, i32]);
        let one = signature(isa, &[pointer, i32]);
        let moves = signature(isa, &[pointer, i32, i32, i32, i32, i32, i32, i32, i32]);
        let mut import = |name: &str, signature: &Signature| -> Result<FuncId, CodegenError> {
            Ok(module.declare_function(name, Linkage::Import, signature)?)
        };
        Ok(Helpers {
            timer_coil: import(names::TIMER_COIL, &coil)?,
            counter_coil: import(names::COUNTER_COIL, &coil)?,
            reset_timer: import(names::RESET_TIMER, &one)?,
            reset_counter: import(names::RESET_COUNTER, &one)?,
            schedule_state_off: import(names::SCHEDULE_STATE_OFF, &one)?,
            block_move: import(names::BLOCK_MOVE, &moves)?,
        })
    }
}

/// Defines the program body `fn(mem)` in `module` under `name`.
fn define_program(
    module: &mut dyn Module,
    program: &Function,
    name: &str,
    linkage: Linkage,
) -> Result<FuncId, CodegenError> {
    let helpers = Helpers::declare(module)?;
    let pointer = module.target_config().pointer_type();
    let body_signature = signature(module.isa(), &[pointer]);
    let id = module.declare_function(name, linkage, &body_signature)?;
    let mut context = module.make_context();
    context.func.signature = body_signature;
    context.func.name = UserFuncName::user(0, id.as_u32());
    let mut builder_context = FunctionBuilderContext::new();
    {
        let mut builder = FunctionBuilder::new(&mut context.func, &mut builder_context);
        let mut reference = |id: FuncId| module.declare_func_in_func(id, builder.func);
        let refs = HelperRefs {
            timer_coil: reference(helpers.timer_coil),
            counter_coil: reference(helpers.counter_coil),
            reset_timer: reference(helpers.reset_timer),
            reset_counter: reference(helpers.reset_counter),
            schedule_state_off: reference(helpers.schedule_state_off),
            block_move: reference(helpers.block_move),
        };
        translate(program, &mut builder, &refs, pointer);
        builder.finalize(module.target_config());
    }
    module.define_function(id, &mut context)?;
    Ok(id)
}
