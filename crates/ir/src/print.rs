//! The text form of the IR (`ladderc build --emit ir`), stable for snapshots.

use super::{BinOp, Cell, Function, Index, Inst, Terminator, Type, UnaryOp};
use std::fmt::{self, Display, Formatter};

impl Display for Type {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Type::Bit => "bit",
            Type::I16 => "i16",
            Type::I32 => "i32",
            Type::I64 => "i64",
            Type::F32 => "f32",
            Type::F64 => "f64",
        })
    }
}

impl Display for super::Value {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        write!(f, "v{}", self.0)
    }
}

impl Display for super::BlockId {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        write!(f, "block{}", self.0)
    }
}

fn index(prefix: &str, name: impl Fn(u32) -> String, index: &Index) -> String {
    match index {
        Index::Fixed(n) => name(*n),
        Index::Dynamic(v) => format!("{prefix}[{v}]"),
    }
}

fn binop(op: BinOp) -> &'static str {
    match op {
        BinOp::Add => "add",
        BinOp::Sub => "sub",
        BinOp::Mul => "mul",
        BinOp::Div => "sdiv",
        BinOp::Rem => "srem",
        BinOp::And => "band",
        BinOp::Or => "bor",
        BinOp::Xor => "bxor",
        BinOp::Shl => "shl",
        BinOp::Shr => "sshr",
        BinOp::UShr => "ushr",
    }
}

fn float_op(op: super::FloatOp) -> &'static str {
    match op {
        super::FloatOp::Add => "fadd",
        super::FloatOp::Sub => "fsub",
        super::FloatOp::Mul => "fmul",
        super::FloatOp::Div => "fdiv",
    }
}

fn float_unary(op: super::FloatUnaryOp) -> &'static str {
    match op {
        super::FloatUnaryOp::SquareRoot => "fsqrt",
        super::FloatUnaryOp::Neg => "fneg",
        super::FloatUnaryOp::Abs => "fabs",
    }
}

fn unop(op: UnaryOp) -> &'static str {
    match op {
        UnaryOp::PopCount => "popcnt",
        UnaryOp::LeadingZeros => "clz",
        UnaryOp::SquareRoot => "isqrt",
    }
}

/// Constant values by the value that holds them, so that helper calls show
/// their constant arguments inline.
type Constants = rustc_hash::FxHashMap<super::Value, i64>;

/// A cell as loads and stores print it: its type and where it is.
fn cell_text(cell: &Cell) -> String {
    match cell {
        Cell::Bit { area, index: i } => format!("bit {}", index(area.prefix(), |n| area.device_name(n), i)),
        Cell::Word { area, index: i } => format!("i16 {}", index(area.prefix(), |n| area.device_name(n), i)),
        Cell::WideCounter { index: i } => format!("i32 {}", index("CN", |n| format!("CN{n}"), i)),
        Cell::Slot { slot } => format!("slot #{slot}"),
        Cell::BlockActive { state } => format!("active S{state}"),
        Cell::Bookkeeping { field, index } => format!("{} #{index}", field.name()),
    }
}

fn inst(func: &Function, constants: &Constants, inst: &Inst) -> String {
    use Inst::*;
    match inst {
        Const { ty, value } => format!("const.{ty} {value}"),
        Load { cell } => format!("load.{}", cell_text(cell)),
        Store { cell, value } => format!("store.{}, {value}", cell_text(cell)),
        FillBits { area, start, count, on } => format!(
            "fill.bit {} x{count}, {}",
            index(area.prefix(), |n| area.device_name(n), start),
            *on as u8
        ),
        ClearWords { area, start, count } => {
            format!(
                "clear.i16 {} x{count}",
                index(area.prefix(), |n| area.device_name(n), start)
            )
        }
        LoadElapsed => "load.elapsed".to_string(),
        GetLocal { local } => format!("get.mc N{}", local.0),
        SetLocal { local, value } => format!("set.mc N{}, {value}", local.0),
        LoadLoopCount { level } => format!("get.loop L{level}"),
        StoreLoopCount { level, value } => format!("set.loop L{level}, {value}"),
        CallSubroutine { subroutine } => format!("call.sub sub{subroutine}"),
        Not { value } => format!("not {value}"),
        And { a, b } => format!("and {a}, {b}"),
        Or { a, b } => format!("or {a}, {b}"),
        Binary { op, a, b } => format!("{}.{} {a}, {b}", binop(*op), func.value_type(*a)),
        Unary { op, value } => format!("{}.{} {value}", unop(*op), func.value_type(*value)),
        Compare { op, a, b } => format!("cmp{} {a}, {b}", op.symbol()),
        Extend { value, to, signed } => {
            format!("{}.{to} {value}", if *signed { "sext" } else { "zext" })
        }
        Truncate { value, to } => format!("trunc.{to} {value}"),
        Select {
            condition,
            if_true,
            if_false,
        } => format!("select {condition}, {if_true}, {if_false}"),
        Float { op, a, b } => format!("{}.{} {a}, {b}", float_op(*op), func.value_type(*a)),
        FloatUnary { op, value } => format!("{}.{} {value}", float_unary(*op), func.value_type(*value)),
        FloatCompare { op, a, b } => format!("fcmp{} {a}, {b}", op.symbol()),
        Bitcast { value, to } => format!("bitcast.{to} {value}"),
        Convert { value, to, conversion } => format!(
            "{}.{to} {value}",
            match conversion {
                super::Conversion::IntToFloat => "itof",
                super::Conversion::FloatToInt => "ftoi",
                super::Conversion::FloatToFloat => "ftof",
            }
        ),
        RecordError { error, line } => format!("record.error {:04X}H, line {line}", error.code()),
        Call { helper, args } => {
            let decl = helper.decl();
            let args: Vec<String> = args
                .iter()
                .map(|v| constants.get(v).map_or_else(|| v.to_string(), i64::to_string))
                .collect();
            format!(
                "call {}({})",
                decl.name.trim_start_matches("ladder_rt_"),
                args.join(", ")
            )
        }
    }
}

/// One instruction as the text form prints it (constant arguments of a
/// helper call shown by their value name), for the verifier's messages.
pub(crate) fn inst_text(func: &Function, instruction: &Inst) -> String {
    inst(func, &Constants::default(), instruction)
}

impl Display for super::Program {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.main)?;
        for (number, subroutine) in self.subroutines.iter().enumerate() {
            let text = subroutine.to_string();
            write!(f, "sub{number}{}", text.strip_prefix("program").unwrap_or(&text))?;
        }
        Ok(())
    }
}

impl Display for Function {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        let constants: Constants = self.constants();
        writeln!(f, "program(mem) {{")?;
        for (number, block) in self.blocks.iter().enumerate() {
            let cold = if block.cold { " (cold)" } else { "" };
            writeln!(f, "block{number}{cold}:")?;
            for (result, instruction) in &block.insts {
                match result {
                    Some(value) => writeln!(f, "    {value} = {}", inst(self, &constants, instruction))?,
                    None => writeln!(f, "    {}", inst(self, &constants, instruction))?,
                }
            }
            match &block.terminator {
                Terminator::Jump(target) => writeln!(f, "    jump {target}")?,
                Terminator::Branch {
                    condition,
                    then,
                    otherwise,
                } => writeln!(f, "    br {condition}, {then}, {otherwise}")?,
                Terminator::Return => writeln!(f, "    return")?,
            }
        }
        writeln!(f, "}}")
    }
}
