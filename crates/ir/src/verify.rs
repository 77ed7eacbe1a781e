//! The IR verifier: the rules every pass and every back end rely on, checked
//! after lowering and after every pass in debug builds and tests
//! (`lower_and_optimize_with`), and once by `ladderc build --emit ir`. A
//! broken pass is then reported by name at the pass, not far away as a
//! panic in a back end's translation or a differential mismatch.
//!
//! The rules:
//! - every value is defined once, by an instruction whose result type is the
//!   value's type, and an instruction defines a value exactly when it has a
//!   result type;
//! - every definition dominates its uses (earlier in the same block, or in a
//!   block that dominates the use's block); blocks the entry cannot reach
//!   are checked for everything else;
//! - every block ends in one terminator (the `Block` type holds one) whose
//!   targets exist, and a branch's condition is a bit;
//! - operand types agree with the instruction (bits for logic, one integer
//!   type for arithmetic and comparisons, one float type for float
//!   operations, widening extensions and narrowing truncations, I32
//!   run-time device numbers and helper arguments);
//! - a constant holds its value as constant folding writes it (sign-extended
//!   from its width; a bit is 0 or 1; a float's bits unsigned);
//! - every fixed device number, edge slot, STL state and timer or counter
//!   lies in its array of the image (a run of SET/RST Kn or ZRST starts in
//!   it; code generation clamps one that is longer than the rest of its
//!   array, as `Effect::Fill` says); locals, loop levels, subroutines and
//!   helper arguments exist.
//!
//! The IR has no block parameters: values cross blocks by dominance, and the
//! master-control power and loop counts live in function locals.

use super::cfg::{reverse_postorder, Dominators};
use super::{BinOp, BlockId, Cell, Conversion, Function, Index, Inst, Program, Terminator, Type, Value};
use std::fmt;

/// Why a program's IR is not well formed: every broken rule found, each
/// with where it is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VerifyError {
    pub problems: Vec<Problem>,
}

/// One broken rule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// `main` or `sub<N>`.
    pub function: String,
    /// The block, when the problem is inside one.
    pub block: Option<BlockId>,
    /// The instruction's position in its block, or `None` for the
    /// terminator or the function as a whole.
    pub position: Option<usize>,
    /// The instruction (or terminator) as text.
    pub text: String,
    pub message: String,
}

impl fmt::Display for VerifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (n, problem) in self.problems.iter().enumerate() {
            if n > 0 {
                writeln!(f)?;
            }
            write!(f, "{}", problem.function)?;
            if let Some(block) = problem.block {
                write!(f, " {block}")?;
            }
            match problem.position {
                Some(position) => write!(f, " inst {position}")?,
                None if problem.block.is_some() => write!(f, " terminator")?,
                None => {}
            }
            write!(f, ": {}", problem.message)?;
            if !problem.text.is_empty() {
                write!(f, " (`{}`)", problem.text)?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for VerifyError {}

/// Checks the main program and every subroutine.
pub fn verify(program: &Program) -> Result<(), VerifyError> {
    let mut problems = Vec::new();
    let subroutines = program.subroutines.len();
    check_function(&program.main, "main", subroutines, &mut problems);
    for (number, subroutine) in program.subroutines.iter().enumerate() {
        check_function(subroutine, &format!("sub{number}"), subroutines, &mut problems);
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(VerifyError { problems })
    }
}

/// Checks one function of a program with `subroutines` subroutines.
pub fn verify_function(function: &Function, name: &str, subroutines: usize) -> Result<(), VerifyError> {
    let mut problems = Vec::new();
    check_function(function, name, subroutines, &mut problems);
    if problems.is_empty() {
        Ok(())
    } else {
        Err(VerifyError { problems })
    }
}

/// Where a value is defined: block and position.
#[derive(Clone, Copy)]
struct Definition {
    block: BlockId,
    position: usize,
}

struct Checker<'f> {
    function: &'f Function,
    name: &'f str,
    subroutines: usize,
    definitions: Vec<Option<Definition>>,
    dominators: Dominators,
    problems: &'f mut Vec<Problem>,
    /// Where the checker is: block and position (`None`: the terminator).
    at: (Option<BlockId>, Option<usize>),
    /// What it is looking at, printed only when it finds a problem.
    looking_at: LookingAt<'f>,
}

#[derive(Clone, Copy)]
enum LookingAt<'f> {
    Nothing,
    Inst(Option<Value>, &'f Inst),
    Terminator(&'f Terminator),
}

fn check_function(function: &Function, name: &str, subroutines: usize, problems: &mut Vec<Problem>) {
    if function.blocks.is_empty() {
        problems.push(Problem {
            function: name.to_string(),
            block: None,
            position: None,
            text: String::new(),
            message: "the function has no blocks (block0 is its entry)".to_string(),
        });
        return;
    }
    let block_count = function.blocks.len();
    let targets_exist = function.blocks.iter().all(|block| {
        block
            .terminator
            .successors()
            .iter()
            .all(|t| (t.0 as usize) < block_count)
    });
    // Dominance needs a graph whose edges all land on blocks; a missing
    // target is reported below and dominance is not checked.
    let dominators = if targets_exist {
        Dominators::new(function, &reverse_postorder(function))
    } else {
        Dominators::new(function, &[])
    };
    let mut checker = Checker {
        function,
        name,
        subroutines,
        definitions: vec![None; function.value_types.len()],
        dominators,
        problems,
        at: (None, None),
        looking_at: LookingAt::Nothing,
    };
    checker.collect_definitions();
    for (number, block) in function.blocks.iter().enumerate() {
        let id = BlockId(number as u32);
        for (position, (result, inst)) in block.insts.iter().enumerate() {
            checker.at = (Some(id), Some(position));
            checker.looking_at = LookingAt::Inst(*result, inst);
            checker.check_inst(*result, inst, targets_exist);
        }
        checker.at = (Some(id), None);
        checker.looking_at = LookingAt::Terminator(&block.terminator);
        checker.check_terminator(&block.terminator, targets_exist);
    }
}

impl Checker<'_> {
    fn problem(&mut self, message: String) {
        let text = match self.looking_at {
            LookingAt::Nothing => String::new(),
            LookingAt::Inst(result, inst) => self.describe(result, inst),
            LookingAt::Terminator(terminator) => format!("{terminator:?}"),
        };
        self.problems.push(Problem {
            function: self.name.to_string(),
            block: self.at.0,
            position: self.at.1,
            text,
            message,
        });
    }

    /// Records every definition; a value defined twice or out of range is a
    /// problem.
    fn collect_definitions(&mut self) {
        let function = self.function;
        for (number, block) in function.blocks.iter().enumerate() {
            let id = BlockId(number as u32);
            for (position, (result, inst)) in block.insts.iter().enumerate() {
                let Some(value) = *result else { continue };
                self.at = (Some(id), Some(position));
                self.looking_at = LookingAt::Inst(*result, inst);
                match self.definitions.get_mut(value.0 as usize) {
                    None => self.problem(format!(
                        "{value} has no type: the function has {} values",
                        function.value_types.len()
                    )),
                    Some(Some(first)) => {
                        let first = *first;
                        self.problem(format!(
                            "{value} is defined again (first in {} inst {})",
                            first.block, first.position
                        ))
                    }
                    Some(slot @ None) => *slot = Some(Definition { block: id, position }),
                }
            }
        }
    }

    /// The instruction as the text form prints it when its values are
    /// well formed, as its structure otherwise.
    fn describe(&self, result: Option<Value>, inst: &Inst) -> String {
        let in_range = |v: Value| (v.0 as usize) < self.function.value_types.len();
        let body = if inst.operands().into_iter().all(in_range) {
            super::print::inst_text(self.function, inst)
        } else {
            format!("{inst:?}")
        };
        match result {
            Some(value) => format!("{value} = {body}"),
            None => body,
        }
    }

    /// The type of an operand, when it is a defined value whose definition
    /// dominates the use.
    fn operand(&mut self, value: Value, reachable_graph: bool) -> Option<Type> {
        let Some(&ty) = self.function.value_types.get(value.0 as usize) else {
            self.problem(format!("{value} is not a value of this function"));
            return None;
        };
        let Some(definition) = self.definitions[value.0 as usize] else {
            self.problem(format!("{value} is used but never defined"));
            return Some(ty);
        };
        let (Some(block), position) = self.at else {
            return Some(ty);
        };
        let dominated = if definition.block == block {
            // The terminator (position None) comes after every instruction.
            position.is_none_or(|p| definition.position < p)
        } else if !reachable_graph || !self.dominators.is_reachable(block) {
            // Dominance means nothing where the entry cannot reach.
            true
        } else {
            self.dominators.dominates(definition.block, block)
        };
        if !dominated {
            self.problem(format!(
                "{value} is used where its definition ({} inst {}) does not dominate",
                definition.block, definition.position
            ));
        }
        Some(ty)
    }

    fn expect_type(&mut self, value: Value, expected: Type, reachable: bool, role: &str) {
        if let Some(ty) = self.operand(value, reachable) {
            if ty != expected {
                self.problem(format!("{role} {value} is {ty}, not {expected}"));
            }
        }
    }

    fn expect_integer(&mut self, value: Value, reachable: bool, role: &str) -> Option<Type> {
        let ty = self.operand(value, reachable)?;
        if !is_integer(ty) {
            self.problem(format!("{role} {value} is {ty}, not an integer"));
        }
        Some(ty)
    }

    fn expect_float(&mut self, value: Value, reachable: bool, role: &str) -> Option<Type> {
        let ty = self.operand(value, reachable)?;
        if !is_float(ty) {
            self.problem(format!("{role} {value} is {ty}, not a float"));
        }
        Some(ty)
    }

    fn same_types(&mut self, a: Option<Type>, b: Option<Type>) {
        if let (Some(a), Some(b)) = (a, b) {
            if a != b {
                self.problem(format!("operands of two types: {a} and {b}"));
            }
        }
    }

    fn check_index(&mut self, index: Index, cell_first: u32, cell_end: u32, what: &str, reachable: bool) {
        match index {
            Index::Fixed(n) => {
                if !(cell_first..cell_end).contains(&n) {
                    self.problem(format!("{what} {n} is outside {cell_first}..{cell_end}"));
                }
            }
            Index::Dynamic(value) => self.expect_type(value, Type::I32, reachable, "run-time index"),
        }
    }

    fn check_cell(&mut self, cell: Cell, reachable: bool) {
        let array = cell.array();
        let index = cell.span().start;
        self.check_index(index, array.first(), array.end(), "element", reachable);
    }

    fn check_inst(&mut self, result: Option<Value>, inst: &Inst, reachable: bool) {
        self.check_operands(inst, reachable);
        let types = &self.function.value_types;
        let result_type = inst.result_type(|v| types.get(v.0 as usize).copied().unwrap_or(Type::I32));
        match (result, result_type) {
            (Some(value), Some(ty)) => {
                if let Some(&declared) = types.get(value.0 as usize) {
                    if declared != ty {
                        self.problem(format!("{value} is declared {declared} but the instruction gives {ty}"));
                    }
                }
            }
            (Some(value), None) => self.problem(format!("{value} is defined by an instruction that gives no value")),
            (None, Some(ty)) => self.problem(format!("the instruction's {ty} value is not given a name")),
            (None, None) => {}
        }
    }

    fn check_operands(&mut self, inst: &Inst, r: bool) {
        match inst {
            Inst::Const { ty, value } => {
                if ty.wrap(*value) != *value {
                    self.problem(format!("constant {value} is not held as a {ty} is"));
                }
            }
            Inst::Load { cell } => self.check_cell(*cell, r),
            Inst::Store { cell, value } => {
                self.check_cell(*cell, r);
                self.expect_type(*value, cell.value_type(), r, "stored value");
            }
            Inst::FillBits { area, start, count, .. } => {
                let array = ladder_runtime::layout::Array::of_bits(*area);
                self.check_run(*start, *count, array, r);
            }
            Inst::ClearWords { area, start, count } => {
                let array = ladder_runtime::layout::Array::of_words(*area);
                self.check_run(*start, *count, array, r);
            }
            Inst::LoadElapsed => {}
            Inst::GetLocal { local } => self.check_local(local.0),
            Inst::SetLocal { local, value } => {
                self.check_local(local.0);
                self.expect_type(*value, Type::Bit, r, "the local's value");
            }
            Inst::LoadLoopCount { level } => self.check_level(*level),
            Inst::StoreLoopCount { level, value } => {
                self.check_level(*level);
                self.expect_type(*value, Type::I32, r, "the loop count");
            }
            Inst::CallSubroutine { subroutine } => {
                if *subroutine as usize >= self.subroutines {
                    self.problem(format!(
                        "sub{subroutine} does not exist ({} subroutines)",
                        self.subroutines
                    ));
                }
            }
            Inst::Not { value } => self.expect_type(*value, Type::Bit, r, "operand"),
            Inst::And { a, b } | Inst::Or { a, b } => {
                self.expect_type(*a, Type::Bit, r, "operand");
                self.expect_type(*b, Type::Bit, r, "operand");
            }
            Inst::Binary { op, a, b } => {
                let ta = self.expect_integer(*a, r, "operand");
                let tb = self.expect_integer(*b, r, "operand");
                match op {
                    // A shift's amount is of the shifted value's type too
                    // (both back ends take it so).
                    BinOp::Add
                    | BinOp::Sub
                    | BinOp::Mul
                    | BinOp::Div
                    | BinOp::Rem
                    | BinOp::And
                    | BinOp::Or
                    | BinOp::Xor
                    | BinOp::Shl
                    | BinOp::Shr
                    | BinOp::UShr => self.same_types(ta, tb),
                }
            }
            Inst::Unary { value, .. } => {
                self.expect_integer(*value, r, "operand");
            }
            Inst::Compare { a, b, .. } => {
                let ta = self.expect_integer(*a, r, "operand");
                let tb = self.expect_integer(*b, r, "operand");
                self.same_types(ta, tb);
            }
            Inst::Extend { value, to, .. } => {
                if let Some(from) = self.expect_integer(*value, r, "operand") {
                    if !is_integer(*to) || to.bits() <= from.bits() {
                        self.problem(format!("an extension from {from} to {to} does not widen an integer"));
                    }
                }
            }
            Inst::Truncate { value, to } => {
                if let Some(from) = self.expect_integer(*value, r, "operand") {
                    if !is_integer(*to) || to.bits() >= from.bits() {
                        self.problem(format!("a truncation from {from} to {to} does not narrow an integer"));
                    }
                }
            }
            Inst::Select {
                condition,
                if_true,
                if_false,
            } => {
                self.expect_type(*condition, Type::Bit, r, "condition");
                let a = self.operand(*if_true, r);
                let b = self.operand(*if_false, r);
                self.same_types(a, b);
            }
            Inst::Float { a, b, .. } | Inst::FloatCompare { a, b, .. } => {
                let ta = self.expect_float(*a, r, "operand");
                let tb = self.expect_float(*b, r, "operand");
                self.same_types(ta, tb);
            }
            Inst::FloatUnary { value, .. } => {
                self.expect_float(*value, r, "operand");
            }
            Inst::Bitcast { value, to } => {
                if let Some(from) = self.operand(*value, r) {
                    let pair = matches!(
                        (from, to),
                        (Type::I32, Type::F32)
                            | (Type::F32, Type::I32)
                            | (Type::I64, Type::F64)
                            | (Type::F64, Type::I64)
                    );
                    if !pair {
                        self.problem(format!(
                            "a bitcast from {from} to {to} is not between an integer and a float of one size"
                        ));
                    }
                }
            }
            Inst::Convert { value, to, conversion } => {
                if let Some(from) = self.operand(*value, r) {
                    let fits = match conversion {
                        Conversion::IntToFloat => is_integer(from) && from != Type::Bit && is_float(*to),
                        Conversion::FloatToInt => is_float(from) && is_integer(*to) && *to != Type::Bit,
                        Conversion::FloatToFloat => is_float(from) && is_float(*to) && from != *to,
                    };
                    if !fits {
                        self.problem(format!("{conversion:?} from {from} to {to}"));
                    }
                }
            }
            Inst::RecordError { .. } => {}
            Inst::Call { helper, args } => {
                let params = helper.decl().params.len();
                if args.len() != params {
                    self.problem(format!(
                        "{} takes {params} arguments, given {}",
                        helper.decl().name,
                        args.len()
                    ));
                }
                for arg in args {
                    self.expect_type(*arg, Type::I32, r, "helper argument");
                }
            }
        }
    }

    fn check_run(&mut self, start: Index, count: u32, array: ladder_runtime::layout::Array, r: bool) {
        self.check_index(start, array.first(), array.end(), "first element", r);
        if count == 0 {
            self.problem("a run of no elements".to_string());
        }
    }

    fn check_local(&mut self, local: u8) {
        if local >= self.function.locals {
            self.problem(format!(
                "local N{local} does not exist ({} locals)",
                self.function.locals
            ));
        }
    }

    fn check_level(&mut self, level: u8) {
        if level >= self.function.loop_levels {
            self.problem(format!(
                "loop level L{level} does not exist ({} levels)",
                self.function.loop_levels
            ));
        }
    }

    fn check_terminator(&mut self, terminator: &Terminator, reachable: bool) {
        let blocks = self.function.blocks.len();
        for target in terminator.successors() {
            if target.0 as usize >= blocks {
                self.problem(format!("{target} does not exist ({blocks} blocks)"));
            }
        }
        match terminator {
            Terminator::Branch { condition, .. } => self.expect_type(*condition, Type::Bit, reachable, "condition"),
            Terminator::Jump(_) | Terminator::Return => {}
        }
    }
}

fn is_integer(ty: Type) -> bool {
    match ty {
        Type::Bit | Type::I16 | Type::I32 | Type::I64 => true,
        Type::F32 | Type::F64 => false,
    }
}

fn is_float(ty: Type) -> bool {
    match ty {
        Type::F32 | Type::F64 => true,
        Type::Bit | Type::I16 | Type::I32 | Type::I64 => false,
    }
}

#[cfg(test)]
#[path = "verify_tests.rs"]
mod tests;
