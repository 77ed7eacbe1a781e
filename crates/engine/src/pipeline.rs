//! The stages after the checker, in order: lowering to IR, IR passes, the
//! image's layout, and code generation. A program is lowered once, into a
//! `Lowered` (whose IR cannot be swapped for another), and every back end
//! builds from that: the pipeline has no entry that lowers again. (The
//! stages themselves stay public to their crates' tests and benchmarks.)

use ladder_codegen::{emit_object, CodegenError, JitProgram, ObjectOptions};
use ladder_front::host_device::HostDevice;
use ladder_front::program::CheckedProgram;
use ladder_ir::image::{compact_layout, machine_use, ImageKind};
use ladder_ir::{Coils, Program};
use ladder_runtime::layout::Layout;

/// A checked program lowered and optimised once, for every back end that
/// builds it (the JIT, the object file, the C back end, full or compact):
/// a scenario runs on four native engines from one lowering.
pub struct Lowered<'p> {
    // Private, with getters: the IR is always the lowering of this
    // checked program, and nothing replaces it.
    checked: &'p CheckedProgram,
    ir: Program,
}

impl<'p> Lowered<'p> {
    /// The checked program it was lowered from.
    pub fn checked(&self) -> &'p CheckedProgram {
        self.checked
    }

    /// Its optimised IR.
    pub fn ir(&self) -> &Program {
        &self.ir
    }

    pub fn new(checked: &'p CheckedProgram) -> Lowered<'p> {
        Lowered::with_coils(checked, Coils::Inline)
    }

    /// Lowered with the timer and counter coils as `coils` says (calls for
    /// a microcontroller's flash).
    pub fn with_coils(checked: &'p CheckedProgram, coils: Coils) -> Lowered<'p> {
        Lowered {
            checked,
            ir: ladder_ir::lower_and_optimize_with(checked, coils),
        }
    }

    /// The program compiled into this process (which runs it on `Memory`:
    /// the full layout).
    pub fn jit(&self) -> Result<JitProgram, CodegenError> {
        JitProgram::compile(&self.ir)
    }

    /// The program as an object file (`options.layout` is set from `image`).
    pub fn object(&self, options: &ObjectOptions, image: &ImageRequest) -> Result<Built<Vec<u8>>, CodegenError> {
        let layout = image.layout(self.checked, &self.ir);
        let options = ObjectOptions {
            layout,
            machine: machine_use(self.checked, &self.ir, &image.host_devices),
            ..options.clone()
        };
        Ok(Built {
            output: emit_object(&self.ir, &options)?,
            layout,
        })
    }

    /// The program as portable C (the C back end; `options.layout` is set
    /// from `image`).
    pub fn c_source(&self, options: &ladder_cback::COptions, image: &ImageRequest) -> Built<String> {
        let layout = image.layout(self.checked, &self.ir);
        let options = ladder_cback::COptions {
            layout,
            machine: machine_use(self.checked, &self.ir, &image.host_devices),
            ..options.clone()
        };
        Built {
            output: ladder_cback::emit_c(&self.ir, &options),
            layout,
        }
    }
}

/// The image a built program gets: the full layout, or a compact one that
/// also holds the devices the host names. Either way the scan keeps up to
/// date the parts of the machine (calendar, scan time, special relays, ...)
/// that the program or the host's devices use.
#[derive(Clone, Debug)]
pub struct ImageRequest {
    pub kind: ImageKind,
    pub host_devices: Vec<HostDevice>,
}

impl Default for ImageRequest {
    fn default() -> Self {
        ImageRequest::full()
    }
}

impl ImageRequest {
    /// Every device (the runtime's `Memory`).
    pub fn full() -> ImageRequest {
        ImageRequest::full_with(Vec::new())
    }

    /// Every device, for a host that reads and writes `host_devices`.
    pub fn full_with(host_devices: Vec<HostDevice>) -> ImageRequest {
        ImageRequest {
            kind: ImageKind::Full,
            host_devices,
        }
    }

    /// The devices the program uses and `host_devices`.
    pub fn compact(host_devices: Vec<HostDevice>) -> ImageRequest {
        ImageRequest {
            kind: ImageKind::Compact,
            host_devices,
        }
    }

    /// The layout for `program`, optimised as `ir`; `None` for the full one.
    pub fn layout(&self, program: &CheckedProgram, ir: &Program) -> Option<Layout> {
        match self.kind {
            ImageKind::Full => None,
            ImageKind::Compact => Some(compact_layout(program, ir, &self.host_devices)),
        }
    }
}

/// What a back end made, and the compact layout it was made for (`None`:
/// the full layout).
#[derive(Clone, Debug)]
pub struct Built<T> {
    pub output: T,
    pub layout: Option<Layout>,
}
