//! The targets Cranelift lacks, reached through the C back end and the
//! system's cross compiler for them: 32-bit Arm microcontrollers and Linux
//! controllers, RISC-V microcontrollers.

/// A target of the C route: its triple, the compilers that build for it
/// (the first one found is used) and their flags.
pub struct CTarget {
    pub triple: &'static str,
    pub compilers: &'static [&'static str],
    pub flags: &'static [&'static str],
    /// The Debian package that provides the compiler.
    pub package: &'static str,
    /// How timers and counters are compiled: calls of the runtime on
    /// microcontrollers (flash), inline on Linux controllers.
    pub coils: ladder_ir::Coils,
}

pub const C_TARGETS: &[CTarget] = &[
    CTarget {
        triple: "thumbv6m-none-eabi",
        compilers: &["arm-none-eabi-gcc"],
        flags: &["-mcpu=cortex-m0", "-mthumb"],
        package: "gcc-arm-none-eabi",
        coils: ladder_ir::Coils::Calls,
    },
    CTarget {
        triple: "thumbv7m-none-eabi",
        compilers: &["arm-none-eabi-gcc"],
        flags: &["-mcpu=cortex-m3", "-mthumb"],
        package: "gcc-arm-none-eabi",
        coils: ladder_ir::Coils::Calls,
    },
    CTarget {
        triple: "thumbv7em-none-eabi",
        compilers: &["arm-none-eabi-gcc"],
        flags: &["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=soft"],
        package: "gcc-arm-none-eabi",
        coils: ladder_ir::Coils::Calls,
    },
    CTarget {
        triple: "thumbv7em-none-eabihf",
        compilers: &["arm-none-eabi-gcc"],
        flags: &["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16"],
        package: "gcc-arm-none-eabi",
        coils: ladder_ir::Coils::Calls,
    },
    CTarget {
        triple: "armv7-unknown-linux-gnueabihf",
        compilers: &["arm-linux-gnueabihf-gcc"],
        flags: &["-march=armv7-a", "-mfloat-abi=hard", "-mfpu=vfpv3-d16", "-fPIC"],
        package: "gcc-arm-linux-gnueabihf",
        coils: ladder_ir::Coils::Inline,
    },
    CTarget {
        triple: "riscv32imac-unknown-none-elf",
        compilers: &["riscv64-unknown-elf-gcc", "riscv32-unknown-elf-gcc"],
        flags: &["-march=rv32imac", "-mabi=ilp32"],
        package: "gcc-riscv64-unknown-elf",
        coils: ladder_ir::Coils::Calls,
    },
];

/// The C route's target for `triple`, if it is one.
pub fn c_target(triple: &str) -> Option<&'static CTarget> {
    C_TARGETS.iter().find(|target| target.triple == triple)
}

impl CTarget {
    /// The first of its compilers that runs on this machine.
    pub fn find_compiler(&self) -> Option<&'static str> {
        self.compilers
            .iter()
            .copied()
            .find(|compiler| crate::cc::runs(compiler))
    }

    /// The command line that builds `file` (a C file of the back end).
    pub fn command_line(&self, compiler: &str, file: &str) -> String {
        format!("{compiler} -std=c99 -O2 {} -c {file}", self.flags.join(" "))
    }

    /// Compiles `source` into an object file with `compiler`.
    pub fn compile(&self, compiler: &str, source: &str) -> Result<Vec<u8>, String> {
        let work = tempfile::tempdir().map_err(|e| e.to_string())?;
        let c = work.path().join("program.c");
        let object = work.path().join("program.o");
        std::fs::write(&c, source).map_err(|e| e.to_string())?;
        crate::cc::run(compiler, &format!("{compiler} failed on the generated C"), |cc| {
            cc.args(["-std=c99", "-O2"])
                .args(self.flags)
                .arg("-c")
                .arg(&c)
                .arg("-o")
                .arg(&object);
        })?;
        std::fs::read(&object).map_err(|e| e.to_string())
    }
}
