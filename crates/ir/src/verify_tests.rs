//! The verifier's tests: every rule broken once, in a function built by
//! hand, must be reported (and nothing else); lowered and optimised programs
//! must pass.

use super::{verify, verify_function};
use crate::{BinOp, Block, BlockId, Cell, Conversion, Function, Index, Inst, Local, Program, Terminator, Type, Value};
use ladder_runtime::helpers::Helper;
use ladder_runtime::{BitArea, WordArea};

/// A block's instructions (with the value each defines) and terminator.
type BlockText = (Vec<(Option<Value>, Inst)>, Terminator);

/// A function of one block per entry of `blocks`, values typed by
/// `value_types`.
fn function(value_types: Vec<Type>, blocks: Vec<BlockText>) -> Function {
    Function {
        blocks: blocks
            .into_iter()
            .map(|(insts, terminator)| Block {
                insts,
                terminator,
                cold: false,
            })
            .collect(),
        value_types,
        locals: 1,
        loop_levels: 1,
    }
}

fn v(n: u32) -> Value {
    Value(n)
}

fn def(n: u32, inst: Inst) -> (Option<Value>, Inst) {
    (Some(Value(n)), inst)
}

fn effect(inst: Inst) -> (Option<Value>, Inst) {
    (None, inst)
}

fn x(n: u32) -> Cell {
    Cell::Bit {
        area: BitArea::X,
        index: Index::Fixed(n),
    }
}

fn y(n: u32) -> Cell {
    Cell::Bit {
        area: BitArea::Y,
        index: Index::Fixed(n),
    }
}

fn d(index: Index) -> Cell {
    Cell::Word {
        area: WordArea::D,
        index,
    }
}

/// The messages of the problems `function` has (none: empty).
fn problems(function: &Function) -> Vec<String> {
    match verify_function(function, "main", 1) {
        Ok(()) => Vec::new(),
        Err(error) => error.problems.into_iter().map(|p| p.message).collect(),
    }
}

/// `function` has exactly one problem, whose message contains `expected`.
#[track_caller]
fn one_problem(function: &Function, expected: &str) {
    let found = problems(function);
    assert!(
        found.len() == 1 && found[0].contains(expected),
        "expected one problem with `{expected}`, found {found:?}"
    );
}

/// `LD X0; OUT Y0` in two blocks, the load's value used across them.
fn well_formed() -> Function {
    function(
        vec![Type::Bit],
        vec![
            (vec![def(0, Inst::Load { cell: x(0) })], Terminator::Jump(BlockId(1))),
            (
                vec![effect(Inst::Store {
                    cell: y(0),
                    value: v(0),
                })],
                Terminator::Return,
            ),
        ],
    )
}

#[test]
fn a_well_formed_function_passes() {
    assert_eq!(problems(&well_formed()), Vec::<String>::new());
}

#[test]
fn a_use_before_its_definition_in_the_block() {
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![
                effect(Inst::Store {
                    cell: y(0),
                    value: v(0),
                }),
                def(0, Inst::Load { cell: x(0) }),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "does not dominate");
}

#[test]
fn a_definition_on_one_arm_used_after_the_join() {
    // block0: br v0 -> block1 (defines v1) | block2; both -> block3 uses v1.
    let f = function(
        vec![Type::Bit, Type::Bit],
        vec![
            (
                vec![def(0, Inst::Load { cell: x(0) })],
                Terminator::Branch {
                    condition: v(0),
                    then: BlockId(1),
                    otherwise: BlockId(2),
                },
            ),
            (vec![def(1, Inst::Load { cell: x(1) })], Terminator::Jump(BlockId(3))),
            (vec![], Terminator::Jump(BlockId(3))),
            (
                vec![effect(Inst::Store {
                    cell: y(0),
                    value: v(1),
                })],
                Terminator::Return,
            ),
        ],
    );
    one_problem(&f, "v1 is used where its definition (block1 inst 0) does not dominate");
}

#[test]
fn a_definition_in_a_loop_header_dominates_the_body() {
    // block0 -> block1 (defines v0) -> block2 (uses v0) -> block1 | block3.
    let f = function(
        vec![Type::Bit],
        vec![
            (vec![], Terminator::Jump(BlockId(1))),
            (vec![def(0, Inst::Load { cell: x(0) })], Terminator::Jump(BlockId(2))),
            (
                vec![effect(Inst::Store {
                    cell: y(0),
                    value: v(0),
                })],
                Terminator::Branch {
                    condition: v(0),
                    then: BlockId(1),
                    otherwise: BlockId(3),
                },
            ),
            (vec![], Terminator::Return),
        ],
    );
    assert_eq!(problems(&f), Vec::<String>::new());
}

#[test]
fn a_value_defined_twice() {
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![def(0, Inst::Load { cell: x(0) }), def(0, Inst::Load { cell: x(1) })],
            Terminator::Return,
        )],
    );
    one_problem(&f, "v0 is defined again (first in block0 inst 0)");
}

#[test]
fn a_value_never_defined_or_without_a_type() {
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![effect(Inst::Store {
                cell: y(0),
                value: v(0),
            })],
            Terminator::Return,
        )],
    );
    one_problem(&f, "v0 is used but never defined");
    let f = function(
        vec![],
        vec![(
            vec![effect(Inst::Store {
                cell: y(0),
                value: v(3),
            })],
            Terminator::Return,
        )],
    );
    one_problem(&f, "v3 is not a value of this function");
}

#[test]
fn a_branch_to_a_missing_block_and_on_a_word() {
    let mut f = well_formed();
    f.blocks[0].terminator = Terminator::Jump(BlockId(7));
    let found = problems(&f);
    assert!(found.iter().any(|p| p.contains("block7 does not exist")), "{found:?}");
    let f = function(
        vec![Type::I16],
        vec![
            (
                vec![def(
                    0,
                    Inst::Load {
                        cell: d(Index::Fixed(0)),
                    },
                )],
                Terminator::Branch {
                    condition: v(0),
                    then: BlockId(1),
                    otherwise: BlockId(1),
                },
            ),
            (vec![], Terminator::Return),
        ],
    );
    one_problem(&f, "condition v0 is i16, not bit");
}

#[test]
fn types_that_disagree() {
    // A word stored into a bit.
    let f = function(
        vec![Type::I16],
        vec![(
            vec![
                def(
                    0,
                    Inst::Load {
                        cell: d(Index::Fixed(0)),
                    },
                ),
                effect(Inst::Store {
                    cell: y(0),
                    value: v(0),
                }),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "stored value v0 is i16, not bit");
    // An addition of an i16 and an i32.
    let f = function(
        vec![Type::I16, Type::I32, Type::I16],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I16,
                        value: 1,
                    },
                ),
                def(
                    1,
                    Inst::Const {
                        ty: Type::I32,
                        value: 1,
                    },
                ),
                def(
                    2,
                    Inst::Binary {
                        op: BinOp::Add,
                        a: v(0),
                        b: v(1),
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "operands of two types: i16 and i32");
    // AND of a word.
    let f = function(
        vec![Type::I16, Type::Bit, Type::Bit],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I16,
                        value: 1,
                    },
                ),
                def(
                    1,
                    Inst::Const {
                        ty: Type::Bit,
                        value: 1,
                    },
                ),
                def(2, Inst::And { a: v(0), b: v(1) }),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "operand v0 is i16, not bit");
    // A value declared with another type than its instruction gives.
    let f = function(
        vec![Type::I32],
        vec![(vec![def(0, Inst::Load { cell: x(0) })], Terminator::Return)],
    );
    one_problem(&f, "v0 is declared i32 but the instruction gives bit");
}

#[test]
fn extensions_truncations_and_conversions_go_the_right_way() {
    let narrowing_extend = function(
        vec![Type::I32, Type::I16],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I32,
                        value: 5,
                    },
                ),
                def(
                    1,
                    Inst::Extend {
                        value: v(0),
                        to: Type::I16,
                        signed: true,
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&narrowing_extend, "does not widen");
    let widening_truncate = function(
        vec![Type::I16, Type::I32],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I16,
                        value: 5,
                    },
                ),
                def(
                    1,
                    Inst::Truncate {
                        value: v(0),
                        to: Type::I32,
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&widening_truncate, "does not narrow");
    let float_to_float_of_an_int = function(
        vec![Type::I32, Type::F64],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I32,
                        value: 5,
                    },
                ),
                def(
                    1,
                    Inst::Convert {
                        value: v(0),
                        to: Type::F64,
                        conversion: Conversion::FloatToFloat,
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&float_to_float_of_an_int, "FloatToFloat from i32 to f64");
    let bitcast_of_sizes = function(
        vec![Type::I16, Type::F32],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I16,
                        value: 5,
                    },
                ),
                def(
                    1,
                    Inst::Bitcast {
                        value: v(0),
                        to: Type::F32,
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&bitcast_of_sizes, "a bitcast from i16 to f32");
}

#[test]
fn constants_are_held_as_folding_holds_them() {
    let f = function(
        vec![Type::I16],
        vec![(
            vec![def(
                0,
                Inst::Const {
                    ty: Type::I16,
                    value: 0xFFFF,
                },
            )],
            Terminator::Return,
        )],
    );
    one_problem(&f, "constant 65535 is not held as a i16 is");
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![def(
                0,
                Inst::Const {
                    ty: Type::Bit,
                    value: 2,
                },
            )],
            Terminator::Return,
        )],
    );
    one_problem(&f, "constant 2 is not held as a bit is");
}

#[test]
fn cells_locals_and_calls_in_range() {
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![def(
                0,
                Inst::Load {
                    cell: Cell::Bit {
                        area: BitArea::M,
                        index: Index::Fixed(BitArea::M.count()),
                    },
                },
            )],
            Terminator::Return,
        )],
    );
    one_problem(&f, "outside 0..");
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![def(
                0,
                Inst::Load {
                    cell: Cell::Slot { slot: u32::MAX },
                },
            )],
            Terminator::Return,
        )],
    );
    one_problem(&f, "outside 0..");
    // A run-time device number must be an I32.
    let f = function(
        vec![Type::I16, Type::I16],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I16,
                        value: 3,
                    },
                ),
                def(
                    1,
                    Inst::Load {
                        cell: d(Index::Dynamic(v(0))),
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "run-time index v0 is i16, not i32");
    let f = function(
        vec![Type::Bit],
        vec![(vec![def(0, Inst::GetLocal { local: Local(1) })], Terminator::Return)],
    );
    one_problem(&f, "local N1 does not exist (1 locals)");
    let f = function(
        vec![],
        vec![(vec![effect(Inst::CallSubroutine { subroutine: 1 })], Terminator::Return)],
    );
    one_problem(&f, "sub1 does not exist (1 subroutines)");
    let f = function(
        vec![Type::I32],
        vec![(
            vec![
                def(
                    0,
                    Inst::Const {
                        ty: Type::I32,
                        value: 3,
                    },
                ),
                effect(Inst::Call {
                    helper: Helper::ResetTimer,
                    args: vec![v(0), v(0)],
                }),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "takes 1 arguments, given 2");
}

#[test]
fn a_result_exactly_when_the_instruction_gives_one() {
    let f = function(
        vec![],
        vec![(vec![effect(Inst::Load { cell: x(0) })], Terminator::Return)],
    );
    one_problem(&f, "the instruction's bit value is not given a name");
    let f = function(
        vec![Type::Bit, Type::Bit],
        vec![(
            vec![
                def(0, Inst::Load { cell: x(0) }),
                def(
                    1,
                    Inst::Store {
                        cell: y(0),
                        value: v(0),
                    },
                ),
            ],
            Terminator::Return,
        )],
    );
    one_problem(&f, "v1 is defined by an instruction that gives no value");
}

#[test]
fn unreachable_blocks_are_checked_but_not_for_dominance() {
    // block1 is unreachable and uses v0 of block0: dominance means nothing
    // there, but its word stored into a bit is still wrong.
    let f = function(
        vec![Type::Bit, Type::I16],
        vec![
            (vec![def(0, Inst::Load { cell: x(0) })], Terminator::Return),
            (
                vec![
                    effect(Inst::Store {
                        cell: y(0),
                        value: v(0),
                    }),
                    def(
                        1,
                        Inst::Load {
                            cell: d(Index::Fixed(1)),
                        },
                    ),
                    effect(Inst::Store {
                        cell: y(1),
                        value: v(1),
                    }),
                ],
                Terminator::Return,
            ),
        ],
    );
    one_problem(&f, "stored value v1 is i16, not bit");
}

#[test]
fn every_problem_is_reported_with_where_it_is() {
    let f = function(
        vec![Type::Bit],
        vec![(
            vec![
                effect(Inst::Store {
                    cell: y(0),
                    value: v(0),
                }),
                def(0, Inst::Load { cell: x(0) }),
            ],
            Terminator::Branch {
                condition: v(0),
                then: BlockId(4),
                otherwise: BlockId(0),
            },
        )],
    );
    let error = verify_function(&f, "sub3", 0).unwrap_err();
    assert_eq!(error.problems.len(), 2, "{error}");
    let text = error.to_string();
    assert!(
        text.contains("sub3 block0 inst 0: v0 is used where its definition (block0 inst 1) does not dominate (`store.bit Y0, v0`)"),
        "{text}"
    );
    assert!(
        text.contains("sub3 block0 terminator: block4 does not exist (1 blocks)"),
        "{text}"
    );
}

/// Every program of the IR's own tests' kind, lowered and optimised, is
/// well formed (the pipeline also verifies after each pass in debug
/// builds; this checks the final product through the public entry).
#[test]
fn lowered_and_optimised_programs_pass() {
    use ladder_front::check::compile_source;
    use ladder_front::source::SourceFile;
    let programs = [
        "LD X0\nOR Y0\nANI X1\nOUT Y0\nEND\n",
        "LD X0\nMC N0 M0\nLD X1\nOUT Y0\nMCR N0\nLD X2\nCJ P1\nOUT T0 K10\nP1\nLD T0\nOUT Y1\nEND\n",
        "FOR K3\nLD SM0\nINC D0Z0\nINC Z0\nNEXT\nLD X0\nCALL P2\nFEND\nP2\nLDP X1\nADD D0 K1 D1\nSRET\nEND\n",
        "LD X0\nSET S20\nSTL S20\nOUT Y0\nLD X1\nSET S21\nSTL S21\nOUT Y1\nLD X2\nOUT S20\nRET\nEND\n",
        "LD X0\nDMOV K100000 D0\nDADD D0 D2 D4\nDEMUL D0 D2 D6\nOUT C200 K5\nEND\n",
    ];
    for text in programs {
        let (program, diagnostics) = compile_source(&SourceFile::new("t.il", text));
        let program = program.unwrap_or_else(|| panic!("{text}: {diagnostics:?}"));
        let ir: Program = crate::lower_and_optimize(&program);
        if let Err(error) = verify(&ir) {
            panic!("{text}\n{error}\n{ir}");
        }
    }
}
