//! One IR function as a C function `static void NAME(uint8_t *m)`.

use ladder_ir::CompareOp;
use ladder_ir::{
    self as ir, BinOp, Cell, Conversion, FloatOp, FloatUnaryOp, Held, Index, Inst, Terminator, Type, UnaryOp, Value,
};
use ladder_runtime::helpers::Helper;
use ladder_runtime::layout::{Array, Layout, Scalar};
use std::collections::{BTreeSet, HashSet};
use std::fmt::Write as _;

/// The helpers a program calls (each declared once, in `Helper::ALL` order).
pub fn used_helpers(program: &ir::Program) -> Vec<Helper> {
    let mut used = BTreeSet::new();
    for function in std::iter::once(&program.main).chain(&program.subroutines) {
        for block in &function.blocks {
            for (_, inst) in &block.insts {
                if let Inst::Call { helper, .. } = inst {
                    used.insert(*helper as usize);
                }
                if let Inst::RecordError { .. } = inst {
                    used.insert(Helper::RecordError as usize);
                }
            }
        }
    }
    used.into_iter().map(|index| Helper::ALL[index]).collect()
}

/// The subroutines the scan body can call (directly or through other
/// subroutines), in number order: only they are emitted (C compilers warn
/// about functions nobody calls).
pub fn called_subroutines(program: &ir::Program) -> Vec<usize> {
    let mut called = BTreeSet::new();
    let mut pending = vec![&program.main];
    while let Some(function) = pending.pop() {
        for block in &function.blocks {
            for (_, inst) in &block.insts {
                if let Inst::CallSubroutine { subroutine } = inst {
                    let number = *subroutine as usize;
                    if let Some(callee) = program.subroutines.get(number) {
                        if called.insert(number) {
                            pending.push(callee);
                        }
                    }
                }
            }
        }
    }
    called.into_iter().collect()
}

fn c_type(ty: Type) -> &'static str {
    match ty {
        Type::Bit => "uint8_t",
        Type::I16 => "int16_t",
        Type::I32 => "int32_t",
        Type::I64 => "int64_t",
        Type::F32 => "float",
        Type::F64 => "double",
    }
}

/// The width suffix of the prelude's integer operations (`ld_add32`).
fn width(ty: Type) -> u32 {
    // A bit is held in a byte.
    ty.bits().max(8)
}

fn compare_operator(op: CompareOp) -> &'static str {
    match op {
        CompareOp::Eq => "==",
        CompareOp::Ne => "!=",
        CompareOp::Gt => ">",
        CompareOp::Lt => "<",
        CompareOp::Ge => ">=",
        CompareOp::Le => "<=",
    }
}

/// A constant of `ty` as a C expression of that type.
fn constant(ty: Type, value: i64) -> String {
    match ty {
        Type::Bit => format!("(uint8_t){}", value as u8),
        Type::I16 => format!("(int16_t){}", value as i16),
        Type::I32 => match value as i32 {
            i32::MIN => "(int32_t)(-2147483647 - 1)".to_string(),
            v => format!("(int32_t){v}"),
        },
        Type::I64 => match value {
            i64::MIN => "(INT64_C(-9223372036854775807) - 1)".to_string(),
            v => format!("INT64_C({v})"),
        },
        Type::F32 => format!("ld_f32_bits(UINT32_C(0x{:08x}))", value as u32),
        Type::F64 => format!("ld_f64_bits(UINT64_C(0x{:016x}))", value as u64),
    }
}

struct Emitter<'a> {
    layout: &'a Layout,
    function: &'a ir::Function,
    /// The body's name; subroutine `n` is `{body}_sub{n}`.
    body: &'a str,
    out: String,
}

impl Emitter<'_> {
    fn v(&self, value: Value) -> String {
        format!("v{}", value.0)
    }

    /// `m + offset` of element `index` of `array`, the index clamped into
    /// the `len` elements from the array's first.
    ///
    /// A device the layout lacks cannot occur (a compact layout is made from
    /// this program's IR), but if it did the access would go to the scalar
    /// that counts layout misses: inside the image, and seen by the tests.
    fn missing(&self) -> String {
        format!("m + {}", Scalar::LayoutMisses.offset())
    }

    fn element(&self, array: Array, len: u32, index: Index) -> String {
        let missing = self.missing();
        let (first, size, len) = (array.first(), array.size(), len.max(1));
        match index {
            Index::Fixed(n) => {
                let n = n.clamp(first, first + len - 1);
                match self.layout.offset(array, n) {
                    // The device named, for whoever reads the C.
                    Some(offset) => format!("m + {offset} /* {} */", ladder_ir::image::device_name(array, n)),
                    None => missing,
                }
            }
            Index::Dynamic(value) => {
                let Some(base) = self.layout.whole(array) else {
                    return missing;
                };
                let index = if first == 0 {
                    self.v(value)
                } else {
                    format!("ld_sub32({}, {first})", self.v(value))
                };
                format!("m + {base} + (size_t)ld_clamp({index}, {}u) * {size}", len - 1)
            }
        }
    }

    /// `count` elements of `array` from `start` set to the byte `byte`
    /// (one `memset` where the image holds the run in one piece).
    fn fill(&self, array: Array, area_count: u32, start: Index, count: u32, byte: u8) -> String {
        let count = count.clamp(1, area_count);
        let size = array.size();
        if let Index::Fixed(n) = start {
            let n = n.clamp(array.first(), array.first() + area_count - count);
            let ends = (self.layout.offset(array, n), self.layout.offset(array, n + count - 1));
            if !matches!(ends, (Some(a), Some(b)) if b - a == (count as usize - 1) * size) {
                // Apart in the image (or missing): element by element.
                let stores: Vec<String> = (0..count)
                    .map(|k| {
                        let at = self.element(array, area_count, Index::Fixed(n + k));
                        format!("memset({at}, {byte}, {size});")
                    })
                    .collect();
                return stores.join(" ");
            }
        }
        let at = self.element(array, area_count - count + 1, start);
        if at == self.missing() {
            // One element's worth at the miss counter, never a run from it.
            return format!("memset({at}, {byte}, {size});");
        }
        format!("memset({at}, {byte}, {});", count as usize * size)
    }

    /// The address of a cell's first byte.
    fn cell_address(&self, cell: &Cell) -> String {
        let array = cell.array();
        self.element(array, array.end() - array.first(), cell.span().start)
    }

    /// The C expression an instruction computes, or the statement it runs
    /// (`Err`) when it defines no value.
    fn inst(&self, inst: &Inst) -> Result<String, String> {
        let ty = |value: &Value| self.function.value_type(*value);
        let v = |value: &Value| self.v(*value);
        Ok(match inst {
            Inst::Const { ty, value } => constant(*ty, *value),
            Inst::Load { cell } => {
                let at = self.cell_address(cell);
                match cell.held() {
                    Held::Bit => format!("*({at})"),
                    // A force byte is FORCE_NONE (0), FORCE_OFF or FORCE_ON.
                    Held::Force => format!("(uint8_t)(*({at}) != 0)"),
                    Held::I16 => format!("ld_load16({at})"),
                    Held::I32 => format!("ld_load32({at})"),
                }
            }
            Inst::Store { cell, value } => {
                let at = self.cell_address(cell);
                return Err(match cell.held() {
                    Held::Bit | Held::Force => format!("*({at}) = {};", v(value)),
                    Held::I16 => format!("ld_store16({at}, {});", v(value)),
                    Held::I32 => format!("ld_store32({at}, {});", v(value)),
                });
            }
            Inst::FillBits { area, start, count, on } => {
                return Err(self.fill(Array::of_bits(*area), area.count(), *start, *count, u8::from(*on)));
            }
            Inst::ClearWords { area, start, count } => {
                return Err(self.fill(Array::of_words(*area), area.count(), *start, *count, 0));
            }
            Inst::LoadElapsed => format!("ld_load32(m + {})", Scalar::ElapsedMs.offset()),
            Inst::GetLocal { local } => format!("l{}", local.0),
            Inst::SetLocal { local, value } => return Err(format!("l{} = {};", local.0, v(value))),
            Inst::LoadLoopCount { level } => format!("c{level}"),
            Inst::StoreLoopCount { level, value } => return Err(format!("c{level} = {};", v(value))),
            Inst::CallSubroutine { subroutine } => return Err(format!("{}_sub{subroutine}(m);", self.body)),
            Inst::Not { value } => format!("(uint8_t)({} ^ 1)", v(value)),
            Inst::And { a, b } => format!("(uint8_t)({} & {})", v(a), v(b)),
            Inst::Or { a, b } => format!("(uint8_t)({} | {})", v(a), v(b)),
            Inst::Binary { op, a, b } => {
                let name = match op {
                    BinOp::Add => "add",
                    BinOp::Sub => "sub",
                    BinOp::Mul => "mul",
                    BinOp::Div => "div",
                    BinOp::Rem => "rem",
                    BinOp::And => "and",
                    BinOp::Or => "or",
                    BinOp::Xor => "xor",
                    BinOp::Shl => "shl",
                    BinOp::Shr => "sshr",
                    BinOp::UShr => "ushr",
                };
                let t = ty(a);
                // Operands and result of the IR's type; bits are 8-bit values.
                format!("({})ld_{name}{}({}, {})", c_type(t), width(t), v(a), v(b))
            }
            Inst::Unary { op, value } => {
                let t = ty(value);
                let name = match op {
                    UnaryOp::PopCount => "popcnt",
                    UnaryOp::LeadingZeros => "clz",
                    UnaryOp::SquareRoot => "isqrt",
                };
                format!("({})ld_{name}{}({})", c_type(t), width(t), v(value))
            }
            Inst::Compare { op, a, b } => {
                let t = ty(a);
                // Signed comparison: bits are compared as 8-bit signed values.
                let (x, y) = if t == Type::Bit {
                    (format!("(int8_t){}", v(a)), format!("(int8_t){}", v(b)))
                } else {
                    (v(a), v(b))
                };
                format!("(uint8_t)({x} {} {y})", compare_operator(*op))
            }
            Inst::Extend { value, to, signed } => {
                let from = ty(value);
                let source = match (from, signed) {
                    (Type::Bit, true) => format!("(int8_t){}", v(value)),
                    (Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64, true) => v(value),
                    (Type::Bit | Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64, false) => {
                        format!("(uint{}_t){}", width(from), v(value))
                    }
                };
                format!("({}){source}", c_type(*to))
            }
            Inst::Truncate { value, to } => match to {
                Type::Bit => format!("(uint8_t){}", v(value)),
                other @ (Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64) => format!(
                    "({})ld_s{}((uint{}_t){})",
                    c_type(*other),
                    width(*other),
                    width(ty(value)).max(32),
                    v(value)
                ),
            },
            Inst::Select {
                condition,
                if_true,
                if_false,
            } => format!("({} ? {} : {})", v(condition), v(if_true), v(if_false)),
            Inst::Float { op, a, b } => {
                let operator = match op {
                    FloatOp::Add => "+",
                    FloatOp::Sub => "-",
                    FloatOp::Mul => "*",
                    FloatOp::Div => "/",
                };
                format!("({})({} {operator} {})", c_type(ty(a)), v(a), v(b))
            }
            Inst::FloatUnary { op, value } => {
                let double = ty(value) == Type::F64;
                match op {
                    FloatUnaryOp::SquareRoot if double => format!("sqrt({})", v(value)),
                    FloatUnaryOp::SquareRoot => format!("sqrtf({})", v(value)),
                    FloatUnaryOp::Neg => format!("(-{})", v(value)),
                    FloatUnaryOp::Abs if double => format!("fabs({})", v(value)),
                    FloatUnaryOp::Abs => format!("fabsf({})", v(value)),
                }
            }
            Inst::FloatCompare { op, a, b } => format!("(uint8_t)({} {} {})", v(a), compare_operator(*op), v(b)),
            Inst::Bitcast { value, to } => match (ty(value), to) {
                (Type::I32, Type::F32) => format!("ld_f32_bits((uint32_t){})", v(value)),
                (Type::I64, Type::F64) => format!("ld_f64_bits((uint64_t){})", v(value)),
                (Type::F32, Type::I32) => format!("ld_f32_to_i32_bits({})", v(value)),
                (Type::F64, Type::I64) => format!("ld_f64_to_i64_bits({})", v(value)),
                (from, to) if from == *to => v(value),
                // The IR makes no other bitcast (Cranelift's verifier would
                // refuse a change of size); a value cast keeps the C valid.
                (Type::Bit | Type::I16 | Type::I32 | Type::I64 | Type::F32 | Type::F64, to) => {
                    format!("({}){}", c_type(*to), v(value))
                }
            },
            Inst::Convert { value, to, conversion } => match conversion {
                Conversion::IntToFloat | Conversion::FloatToFloat => format!("({}){}", c_type(*to), v(value)),
                Conversion::FloatToInt => {
                    format!("({})ld_sat{}((double){})", c_type(*to), width(*to), v(value))
                }
            },
            Inst::RecordError { error, line } => {
                return Err(format!(
                    "{}((LadderMemory *)m, {}u, {}u);",
                    Helper::RecordError.decl().name,
                    error.code(),
                    line
                ))
            }
            Inst::Call { helper, args } => {
                let mut call = format!("{}((LadderMemory *)m", helper.decl().name);
                for arg in args {
                    let _ = write!(call, ", {}", v(arg));
                }
                call.push(')');
                if helper.decl().returns.is_some() {
                    call
                } else {
                    return Err(format!("{call};"));
                }
            }
        })
    }
}

/// Appends `static void name(uint8_t *m)` for `function`; subroutine `n`
/// is `{body}_sub{n}`.
pub fn emit(out: &mut String, layout: &Layout, function: &ir::Function, name: &str, body: &str) {
    let mut emitter = Emitter {
        layout,
        function,
        body,
        out: String::new(),
    };
    // Values that are read somewhere: only they get a variable.
    let mut used: HashSet<Value> = HashSet::new();
    let mut targets: HashSet<u32> = HashSet::new();
    for (number, block) in function.blocks.iter().enumerate() {
        for (_, inst) in &block.insts {
            used.extend(inst.operands());
        }
        match &block.terminator {
            Terminator::Jump(to) => {
                // A jump to the next block falls through: no label needed.
                if to.0 as usize != number + 1 {
                    targets.insert(to.0);
                }
            }
            Terminator::Branch {
                condition,
                then,
                otherwise,
            } => {
                used.insert(*condition);
                targets.insert(then.0);
                targets.insert(otherwise.0);
            }
            Terminator::Return => {}
        }
    }
    let _ = writeln!(emitter.out, "static void {name}(uint8_t *m) {{");
    emitter.out.push_str("    (void)m;\n");
    let mut declared: Vec<&Value> = used.iter().collect();
    declared.sort();
    for value in declared {
        // Initialised: a compiler cannot always see that a value is set on
        // every path to its use (it is: the IR is in SSA form).
        let _ = writeln!(
            emitter.out,
            "    {} v{} = 0;",
            c_type(function.value_type(*value)),
            value.0
        );
    }
    for local in 0..function.locals {
        let _ = writeln!(emitter.out, "    uint8_t l{local} = 0;\n    (void)l{local};");
    }
    for level in 0..function.loop_levels {
        let _ = writeln!(emitter.out, "    int32_t c{level} = 0;\n    (void)c{level};");
    }
    for (number, block) in function.blocks.iter().enumerate() {
        if targets.contains(&(number as u32)) {
            let _ = writeln!(emitter.out, "b{number}:;");
        }
        for (result, inst) in &block.insts {
            let line = match emitter.inst(inst) {
                Err(statement) => statement,
                Ok(expression) => match result {
                    Some(value) if used.contains(value) => format!("v{} = {expression};", value.0),
                    // A value nobody reads: only a call has an effect.
                    _ if matches!(inst, Inst::Call { .. }) => format!("(void){expression};"),
                    _ => continue,
                },
            };
            let _ = writeln!(emitter.out, "    {line}");
        }
        let next = number + 1;
        let line = match &block.terminator {
            Terminator::Jump(to) if to.0 as usize == next => continue,
            Terminator::Jump(to) => format!("goto b{};", to.0),
            Terminator::Branch {
                condition,
                then,
                otherwise,
            } => format!(
                "if ({}) goto b{}; else goto b{};",
                emitter.v(*condition),
                then.0,
                otherwise.0
            ),
            Terminator::Return => "return;".to_string(),
        };
        let _ = writeln!(emitter.out, "    {line}");
    }
    emitter.out.push_str("}\n\n");
    out.push_str(&emitter.out);
}
