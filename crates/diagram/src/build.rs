//! Building the ladder of a checked program: rungs cut where the logic
//! stack starts over, each rebuilt from its instructions.

use super::{Body, Element, Ladder, Node, Rung, Tail, TailItem};
use ladder_front::program::{CheckedProgram, Contact, Line, Logic, Op, Output};
use ladder_front::source::SourceFile;
use ladder_runtime::Width;

/// How the source closed an STL block where the checker's StlEnd stands:
/// `STLE`, `RET`, or (FX style) the next `STL`, as written in plain IL or in
/// an export's row.
fn written_mnemonic(source: &SourceFile, span: ladder_front::source::Span) -> &'static str {
    let written = source.slice(span).to_ascii_uppercase();
    let words: Vec<&str> = written
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .collect();
    if words.contains(&"STLE") {
        "STLE"
    } else if words.contains(&"RET") {
        "RET"
    } else {
        "STL"
    }
}

/// The ladder of `program`, whose source is `source` (for comments, step
/// numbers and how STL blocks were closed).
pub fn build(program: &CheckedProgram, source: &SourceFile) -> Ladder {
    let steps = steps(program, source);
    let comments = comment_lines(source);
    let notes = notes(source);
    let device_comments: super::DeviceComments =
        std::sync::Arc::new(ladder_front::gxdev::listing::device_comments(&source.text));
    let element = |index: usize| {
        let instruction = &program.instructions[index];
        Element {
            index,
            span: instruction.span,
            line: instruction.line,
            step: steps[index],
            note: notes.get(&instruction.line).cloned(),
        }
    };
    let mut rungs = Vec::new();
    let mut state = None;
    let mut mc_levels = 0u8;
    let mut comment_from = 0u32;
    let mut index = 0;
    while index < program.instructions.len() {
        let instruction = &program.instructions[index];
        // FX style: the next STL closes the open block without a RET (the
        // checker's StlEnd stands at that STL). Nothing is drawn for it, as
        // GX Works2 draws nothing: the ladder shows what the program says.
        if instruction.op == Op::Line(Line::StlEnd) && written_mnemonic(source, instruction.span) == "STL" {
            index += 1;
            continue;
        }
        let (body, used) = match &instruction.op {
            Op::Line(Line::StlBegin { block }) => {
                let number = program.stl_blocks.get(*block).map_or(0, |b| b.state);
                state = Some(number);
                (
                    Body::Step {
                        state: number,
                        element: element(index),
                    },
                    1,
                )
            }
            Op::Line(Line::StlEnd) => {
                state = None;
                let fx_return = written_mnemonic(source, instruction.span) != "STLE";
                (
                    Body::StepEnd {
                        fx_return,
                        element: element(index),
                    },
                    1,
                )
            }
            Op::Line(Line::Label { number }) => (
                Body::Label {
                    number: *number,
                    element: element(index),
                },
                1,
            ),
            Op::Line(Line::MasterControlReset { level }) => {
                mc_levels &= (1u8 << level).wrapping_sub(1);
                (
                    Body::MasterControlReset {
                        level: *level,
                        element: element(index),
                    },
                    1,
                )
            }
            Op::Line(Line::MainEnd | Line::SubroutineReturn | Line::LoopStart { .. } | Line::LoopEnd { .. }) => (
                Body::Rail {
                    element: element(index),
                },
                1,
            ),
            Op::Load { mc_levels: levels, .. } => {
                mc_levels = *levels;
                let end = rung_end(program, index);
                (logic(program, index, end, &element), end - index)
            }
            // A rung always starts with a load; anything else here is a
            // part of a rung the checker accepted in a shape this builder
            // does not know: shown alone rather than lost.
            Op::And(_) | Op::Or(_) | Op::Logic(_) | Op::Output(_) | Op::Jump { .. } | Op::Call { .. } => (
                Body::Rail {
                    element: element(index),
                },
                1,
            ),
        };
        let line = instruction.line;
        let rung_comments = comments
            .iter()
            .filter(|(at, _)| (comment_from..line).contains(at))
            .map(|(_, text)| text.clone())
            .collect();
        let last_line = program.instructions[index + used - 1].line;
        comment_from = last_line + 1;
        let in_state = match body {
            Body::Step { .. } | Body::StepEnd { .. } => None,
            Body::Logic { .. } | Body::Label { .. } | Body::MasterControlReset { .. } | Body::Rail { .. } => state,
        };
        rungs.push(Rung {
            step: steps[index],
            line,
            comments: rung_comments,
            state: in_state,
            mc_levels,
            body,
            device_comments: device_comments.clone(),
        });
        if let Op::Output(Output::MasterControl { level, .. }) = &program.instructions[index + used - 1].op {
            mc_levels |= 1 << level;
        }
        index += used;
    }
    Ladder {
        name: program.name.clone(),
        rungs,
    }
}

/// Where the rung that starts at `start` ends: at the next rung's first
/// load, or at the next instruction that is a line of its own.
fn rung_end(program: &CheckedProgram, start: usize) -> usize {
    let mut end = start + 1;
    while let Some(instruction) = program.instructions.get(end) {
        let boundary = match &instruction.op {
            Op::Load { new_rung, .. } => *new_rung,
            Op::Line(_) => true,
            Op::And(_) | Op::Or(_) | Op::Logic(_) | Op::Output(_) | Op::Jump { .. } | Op::Call { .. } => false,
        };
        if boundary {
            break;
        }
        end += 1;
    }
    end
}

/// The instructions of one rung as a network and its tail.
fn logic(program: &CheckedProgram, start: usize, end: usize, element: &dyn Fn(usize) -> Element) -> Body {
    let mut reader = Reader {
        program,
        element,
        at: start,
        end,
    };
    // The state's power (the checker's load for an output right after
    // STL) is not a contact of the source: the rung starts at the rail.
    let synthetic = matches!(
        &program.instructions[start].op,
        Op::Load {
            contact: Contact::Constant(true),
            ..
        }
    ) && program
        .instructions
        .get(start + 1)
        .is_some_and(|next| next.span == program.instructions[start].span);
    let condition = if synthetic {
        reader.at += 1;
        Node::Power
    } else {
        let mut stack = Vec::new();
        while reader.at < end && reader.contact_op(&mut stack) {}
        stack.pop().unwrap_or(Node::Power)
    };
    let tail = reader.tail(false);
    Body::Logic { condition, tail }
}

struct Reader<'a> {
    program: &'a CheckedProgram,
    element: &'a dyn Fn(usize) -> Element,
    at: usize,
    end: usize,
}

/// `a` and then `b` in series (flattened).
fn series(a: Node, b: Node) -> Node {
    match a {
        Node::Series(mut nodes) => {
            nodes.push(b);
            Node::Series(nodes)
        }
        Node::Element(_) | Node::Power | Node::Parallel(_) | Node::Block(_) => Node::Series(vec![a, b]),
    }
}

/// `a` or `b` in parallel (flattened).
fn parallel(a: Node, b: Node) -> Node {
    match a {
        Node::Parallel(mut nodes) => {
            nodes.push(b);
            Node::Parallel(nodes)
        }
        Node::Element(_) | Node::Power | Node::Series(_) | Node::Block(_) => Node::Parallel(vec![a, b]),
    }
}

impl Reader<'_> {
    fn op(&self) -> Option<&Op> {
        (self.at < self.end).then(|| &self.program.instructions[self.at].op)
    }

    /// Applies one contact or block instruction to the block stack; false
    /// (nothing consumed) for anything else.
    fn contact_op(&mut self, stack: &mut Vec<Node>) -> bool {
        let Some(op) = self.op() else { return false };
        let here = Node::Element((self.element)(self.at));
        let top = |stack: &mut Vec<Node>| stack.pop().unwrap_or(Node::Power);
        match op {
            Op::Load { .. } => stack.push(here),
            Op::And(_) | Op::Logic(Logic::Invert | Logic::ResultEdge { .. }) => {
                let a = top(stack);
                stack.push(series(a, here));
            }
            Op::Or(_) => {
                let a = top(stack);
                stack.push(parallel(a, here));
            }
            Op::Logic(Logic::AndBlock | Logic::OrBlock) => {
                let b = top(stack);
                let a = top(stack);
                let block = Node::Block(Box::new(b));
                stack.push(if matches!(op, Op::Logic(Logic::AndBlock)) {
                    series(a, block)
                } else {
                    parallel(a, block)
                });
            }
            Op::Logic(Logic::BranchPush | Logic::BranchRead | Logic::BranchPop)
            | Op::Output(_)
            | Op::Jump { .. }
            | Op::Call { .. }
            | Op::Line(_) => return false,
        }
        self.at += 1;
        true
    }

    /// The tail from here: outputs, contacts between them, splits. A branch
    /// (`nested`) ends before the MRD or MPP of its split.
    fn tail(&mut self, nested: bool) -> Tail {
        let mut items = Vec::new();
        let mut stack = vec![Node::Power];
        let flush = |items: &mut Vec<TailItem>, stack: &mut Vec<Node>| {
            let node = stack.pop().unwrap_or(Node::Power);
            // Blocks still open (never the case in a checked rung) stay
            // visible as contacts.
            for open in stack.drain(..) {
                items.push(TailItem::Contacts(open));
            }
            if node != Node::Power {
                items.push(TailItem::Contacts(node));
            }
            stack.push(Node::Power);
        };
        while let Some(op) = self.op() {
            match op {
                Op::Logic(Logic::BranchRead | Logic::BranchPop) if nested => break,
                Op::Logic(Logic::BranchPush) => {
                    self.at += 1;
                    flush(&mut items, &mut stack);
                    let mut branches = vec![self.tail(true)];
                    while let Some(next @ Op::Logic(Logic::BranchRead | Logic::BranchPop)) = self.op() {
                        let last = matches!(next, Op::Logic(Logic::BranchPop));
                        self.at += 1;
                        // The branch after MPP runs to the end of this tail.
                        branches.push(self.tail(if last { nested } else { true }));
                        if last {
                            break;
                        }
                    }
                    items.push(TailItem::Split(branches));
                    return Tail { items };
                }
                Op::Output(_) | Op::Jump { .. } | Op::Call { .. } => {
                    flush(&mut items, &mut stack);
                    items.push(TailItem::Output((self.element)(self.at)));
                    self.at += 1;
                }
                Op::Logic(Logic::BranchRead | Logic::BranchPop)
                | Op::Load { .. }
                | Op::And(_)
                | Op::Or(_)
                | Op::Logic(Logic::AndBlock | Logic::OrBlock | Logic::Invert | Logic::ResultEdge { .. })
                | Op::Line(_) => {
                    // MRD/MPP outside a split and lines of their own cannot
                    // be inside a checked rung; stop rather than loop.
                    if !self.contact_op(&mut stack) {
                        break;
                    }
                }
            }
        }
        flush(&mut items, &mut stack);
        Tail { items }
    }
}

/// The step of every instruction: the number the source line starts with
/// (a listing's or an export's step column), else counted from the last
/// known one with FX3U step sizes.
fn steps(program: &CheckedProgram, source: &SourceFile) -> Vec<u32> {
    let mut next = 0u32;
    program
        .instructions
        .iter()
        .map(|instruction| {
            let written = written_step(source, instruction.line);
            let step = written.unwrap_or(next);
            next = step + step_size(&instruction.op);
            step
        })
        .collect()
}

/// A step number at the start of source line `line` (`12 LD X0`,
/// `"12"\t...`, `12,,LD,...`).
fn written_step(source: &SourceFile, line: u32) -> Option<u32> {
    let starts = source.line_starts();
    let start = *starts.get(line.checked_sub(1)? as usize)?;
    let text = source.text[start..].trim_start_matches(['\u{feff}', ' ', '\t', '"']);
    let digits: String = text.chars().take_while(char::is_ascii_digit).collect();
    let after = text[digits.len()..].chars().next();
    let separated = matches!(after, Some(' ' | '\t' | ',' | '"'));
    (separated && !digits.is_empty()).then(|| digits.parse().ok()).flatten()
}

/// Steps an instruction takes in an FX3U program.
fn step_size(op: &Op) -> u32 {
    let contact = |contact: &Contact| match contact {
        Contact::Level { .. } | Contact::Constant(_) => 1,
        Contact::Edge { .. } => 2,
        Contact::Compare { width, .. } => match width {
            Width::Single => 5,
            Width::Double => 9,
        },
    };
    match op {
        Op::Load { contact: c, .. } | Op::And(c) | Op::Or(c) => contact(c),
        Op::Logic(_)
        | Op::Line(
            Line::Label { .. }
            | Line::StlBegin { .. }
            | Line::StlEnd
            | Line::MainEnd
            | Line::SubroutineReturn
            | Line::LoopEnd { .. },
        ) => 1,
        Op::Line(Line::MasterControlReset { .. }) => 2,
        Op::Jump { .. } | Op::Call { .. } | Op::Line(Line::LoopStart { .. }) => 3,
        Op::Output(output) => match output {
            Output::Coil(_) | Output::Set { .. } | Output::StateJump { .. } => 1,
            Output::Reset { .. } | Output::Pulse { .. } => 2,
            Output::Timer { .. } | Output::MasterControl { .. } => 3,
            Output::Counter { counter, .. } => {
                if *counter >= ladder_runtime::device::FIRST_WIDE_COUNTER {
                    5
                } else {
                    3
                }
            }
            Output::App(app) => {
                let per_operand = match app.width {
                    Width::Single => 2,
                    Width::Double => 4,
                };
                1 + per_operand * app.args.operands().len() as u32
            }
        },
    }
}

/// Comment lines of the source: `//` or `;` lines of IL and the title of
/// a `NETWORK n // title` line, line statements of an export's comment
/// rows. (line, text). `//@` lines (a project's CPU, parameters and device
/// comments) are not rung comments.
fn comment_lines(source: &SourceFile) -> Vec<(u32, String)> {
    if ladder_front::syntax::export::is_export(&source.text) {
        return ladder_front::syntax::export::comment_rows(source);
    }
    source
        .text
        .lines()
        .enumerate()
        .filter_map(|(index, line)| {
            let trimmed = line.trim_start_matches('\u{feff}').trim();
            if ladder_front::gxdev::listing::is_directive(trimmed) {
                return None;
            }
            let text = match trimmed.strip_prefix("//").or_else(|| trimmed.strip_prefix(';')) {
                Some(text) => text,
                None if starts_with_word(trimmed, "NETWORK") => trailing_comment(trimmed)?,
                None => return None,
            };
            Some((index as u32 + 1, text.trim().to_string()))
        })
        .filter(|(_, text)| !text.is_empty())
        .collect()
}

fn starts_with_word(line: &str, word: &str) -> bool {
    line.get(..word.len())
        .is_some_and(|start| start.eq_ignore_ascii_case(word))
        && line[word.len()..].chars().next().is_none_or(char::is_whitespace)
}

/// The `// comment` after an instruction on its line.
fn trailing_comment(line: &str) -> Option<&str> {
    line.find("//").map(|at| &line[at + 2..])
}

/// The comment after the instruction of each source line (IL only: an
/// export keeps its notes in a column of its own), by line.
fn notes(source: &SourceFile) -> std::collections::HashMap<u32, String> {
    if ladder_front::syntax::export::is_export(&source.text) {
        return Default::default();
    }
    source
        .text
        .lines()
        .enumerate()
        .filter_map(|(index, line)| {
            let note = trailing_comment(line.trim())?.trim();
            let instruction = !line.trim().starts_with("//") && !starts_with_word(line.trim(), "NETWORK");
            (instruction && !note.is_empty()).then(|| (index as u32 + 1, note.to_string()))
        })
        .collect()
}
