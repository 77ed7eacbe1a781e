//! Stable diagnostic codes. A code, once published, keeps its meaning; new
//! kinds get new codes. `ladderc explain CODE` prints the explanation.

use super::Severity;

macro_rules! codes {
    ($( $variant:ident = $code:literal, $severity:ident, $title:literal, $explanation:literal; )*) => {
        /// Every kind of diagnostic the front end reports.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code { $( $variant, )* }

        impl Code {
            pub const ALL: &'static [Code] = &[ $( Code::$variant, )* ];

            /// The stable code, e.g. `E0001`.
            pub fn as_str(self) -> &'static str {
                match self { $( Code::$variant => $code, )* }
            }

            pub fn severity(self) -> Severity {
                match self { $( Code::$variant => Severity::$severity, )* }
            }

            /// One line saying what the code is about.
            pub fn title(self) -> &'static str {
                match self { $( Code::$variant => $title, )* }
            }

            /// A short explanation with an example and the fix.
            pub fn explanation(self) -> &'static str {
                match self { $( Code::$variant => $explanation, )* }
            }
        }
    };
}

codes! {
    UnknownMnemonic = "E0001", Error, "unknown instruction",
"The first word of the line is not an instruction of the dialect.

    LDD X0      // error: LDD is not an instruction (did you mean LD?)

Mnemonics are case-insensitive. Application instructions take a `P` suffix
for the pulse form (MOVP) and a `D` prefix for the 32-bit form (DMOV) only
where the instruction has one.";

    OperandCount = "E0002", Error, "wrong number of operands",
"The instruction takes a fixed number of operands (some have an optional
last operand, such as the count of SET/RST).

    ADD D0 D1   // error: ADD takes (S1) (S2) (D)";

    OperandKind = "E0003", Error, "operand of the wrong kind",
"The operand is valid in general but not in this position: a word device
where a bit is needed (SET D0), a constant as a destination (MOV D0 K1),
an input as an output (OUT X0), a 32-bit counter in a 16-bit instruction,
or a timer without a preset.";

    DeviceRange = "E0004", Error, "device number out of range",
"The device number is outside its area: X/Y 0-377 (octal), M0-M8511,
S0-S4095, SM0-SM1023, T0-T511, C0-C255, D0-D8511, SD0-SD1023, R0-R32767.
A 32-bit operand also needs its high word (n+1) in range, and a digit
group KnM0 needs all 4n bits.";

    MalformedOperand = "E0005", Error, "malformed operand",
"The operand cannot be read as a device or a constant: an 8 or 9 in an
octal X/Y number (X8), a non-hex digit in an H constant, a bit number that
is not one hex digit (D0.G), an unclosed offset (D0[D1), or a digit count
outside 1-8 (K9M0).";

    ConstantRange = "E0006", Error, "constant out of range",
"The constant does not fit where it is used: 16-bit operands take
K-32768..K32767 or H0..HFFFF, 32-bit operands K-2147483648..K2147483647 or
H0..HFFFFFFFF; counts and presets have their own ranges.";

    MissingPreset = "E0007", Error, "timer or counter coil without a preset",
"`OUT Tn` and `OUT Cn` need the preset as a second operand, a constant or a
data register:

    OUT T0 K10  // 1 s on a 100 ms timer
    OUT C3 D100";

    MalformedLine = "E0008", Error, "malformed line",
"The line is not `[step] MNEMONIC operands...` or a label alone on its
line (`P12` or `P12:`). A stray comma or a step number without an
instruction also gives this error.";

    BinaryInput = "E0009", Error, "not a text file",
"The file holds a NUL byte, so it is binary data (an object file, an image)
rather than a program. Program files are text: UTF-8 (with or without a
byte-order mark), UTF-16 with a byte-order mark, or a GX Works2 instruction
list exported as CSV.";

    BlockUnderflow = "E0010", Error, "ANB/ORB without two blocks",
"ANB and ORB combine the current block with the one before it; a block
starts at each LD-type instruction. There must be a block pending:

    LD X0
    LD X1       // second block
    ORB         // X0 OR X1";

    StackUnderflow = "E0011", Error, "MRD/MPP without MPS",
"MRD reads and MPP pops the branch point pushed by MPS. Each MPP needs an
MPS before it in the same rung.";

    StackOverflow = "E0012", Error, "MPS nested deeper than 11",
"The branch stack holds 11 entries. Restructure the rung or split it.";

    PendingBlocks = "E0013", Error, "blocks not combined",
"A block started with LD/LDI was never combined with ANB or ORB before the
rung's output, a POP, or the end of the rung. Add the missing ANB/ORB.";

    OpenBranch = "E0014", Error, "MPS without MPP",
"The rung ends while a branch point pushed by MPS is still open. Close the
last branch with MPP.";

    NoRung = "E0015", Error, "contact without a rung start",
"A series or parallel contact (AND, OR, ...), ANB/ORB, MPS or INV needs a
rung that was started by an LD-type instruction.";

    NoCondition = "E0016", Error, "output without a condition",
"Every output and application instruction takes the result of its rung;
start the rung with a contact (use LD SM0 or LD M8000 for 'always').";

    NoOutput = "E0017", Error, "rung without an output",
"The rung's contacts are never used: the rung ends (POP, NETWORK, a new
rung, STLE, END) before any output or application instruction.";

    NestedStl = "E0020", Error, "STL inside an STL block",
"A program that contains STLE pairs every STL with its own STLE (\"STL and
STLE must be paired one by one ... cannot be nested\"), so an STL while a
block is open is an error:

    STL S20
    OUT Y0
    STL S21     // error: the block of S20 is still open
    STLE

Close each block with STLE before the next STL. A program without STLE is
read FX style: the next STL (or RET) closes the open block.

    STL S20
    OUT Y0
    STL S21     // closes the block of S20
    OUT Y1
    RET         // closes the block of S21";

    DuplicateState = "E0021", Error, "state used by two STL blocks",
"One state number has one block. Use another state, or put the rungs in
the existing block.";

    UnclosedStl = "E0022", Error, "STL block never closed",
"Every `STL Sn` block ends at the next STL, at STLE or at RET. The error
points at the STL whose block is still open at END or FEND:

    STL S20
    OUT Y0
    FEND        // error: close the block with RET first";

    StrayStle = "E0023", Error, "STLE or RET without STL",
"STLE and RET close a state block; there is no open block here.";

    NotInStl = "E0024", Error, "instruction not allowed in an STL block",
"MC and MCR are not allowed between STL and STLE: a state block already
gates its rungs, and a master-control region must not straddle a block.";

    McPairing = "E0025", Error, "MC/MCR do not pair",
"`MC Nk dev` opens master-control level k and `MCR Nk` closes it (and every
deeper level). Levels nest in increasing order N0 < N1 < ... < N7, every
MCR needs an open MC of its level, and every MC needs an MCR.";

    MissingLabel = "E0026", Error, "jump to a missing label",
"`CJ Pn` needs the label Pn somewhere after it, alone on a line.";

    DuplicateLabel = "E0027", Error, "label defined twice",
"Each label Pn marks one place in the program.";

    BackwardJump = "E0028", Error, "backward jump",
"ladderc accepts forward jumps only: a backward CJ can loop forever inside
one scan, which a PLC catches with its watchdog and a compiled program on a
PC would hang on. Use a loop over scans instead.";

    JumpIntoBlock = "E0029", Error, "jump into an STL block or MC region",
"A CJ may leave an STL block or master-control region but not enter one,
because the block's state gating or the region's MC would be skipped.";

    TooManyEdges = "E0030", Error, "too many edge instructions",
"Each edge instruction (LDP, PLS, MOVP, ...) owns one previous-scan slot,
and a program has 16384 of them.";

    TooManyJobs = "E0031", Error, "too many instructions that keep state between scans",
"The device image has room for 64 sorts (SORT, SORT2, DSORT2) and 256 other
instructions that keep their state between scans (HOUR, TTMR, STMR, RAMP,
SEGL, DHSCS, DHSCR, DHSZ, the pulse and positioning outputs, PWM, PID): each
keeps its progress there from one scan to the next.";

    UnsupportedFx = "E0032", Error, "FX instruction not supported",
"The instruction exists on Mitsubishi FX PLCs but ladderc does not implement
it (yet). `ladderc explain` and docs/language.md list what is supported;
rewrite the rung with supported instructions.

    REF X0 K8   // error: FX instruction `REF` is not supported";

    NotASubroutine = "E0033", Error, "CALL to a label that is not a subroutine",
"`CALL Pn` needs Pn to start a subroutine: a label after FEND, followed by
the subroutine's instructions and SRET. A label in the main program is a CJ
target only.

    LD X0
    CALL P1
    FEND
    P1          // the subroutine
    LD X1
    OUT Y1
    SRET";

    Recursion = "E0034", Error, "recursive subroutine call",
"A subroutine calls itself, directly or through other subroutines. An FX
PLC has no call stack for that; the error points at the CALL that closes
the cycle.";

    MissingSret = "E0035", Error, "subroutine without SRET",
"A subroutine runs from its label to SRET. The error points at the label
of a subroutine whose SRET is missing before FEND, END or the end of the
file.";

    StraySret = "E0036", Error, "SRET outside a subroutine",
"SRET ends a subroutine; here no subroutine is open (subroutines start at a
label after FEND).";

    JumpAcrossSubroutine = "E0037", Error, "jump between program parts",
"A CJ jumps within the main program or within one subroutine. Use CALL to
run a subroutine.";

    CallTooDeep = "E0038", Error, "subroutine calls nested too deep",
"Calls nest up to 5 levels: the main program calls a subroutine (level 1),
which may call another (level 2), and so on up to level 5. The error
points at the CALL that would be level 6.";

    OutsideSubroutine = "E0039", Error, "instruction after FEND outside a subroutine",
"After FEND only subroutines follow: a label Pn, its instructions, SRET.
Instructions between an SRET and the next label (or right after FEND) would
never run.";

    NotInSubroutine = "E0040", Error, "instruction not allowed in a subroutine",
"STL blocks and MC/MCR master-control regions belong to the main program; a
subroutine runs only when called, so it cannot hold them.";

    LoopPairing = "E0041", Error, "FOR/NEXT do not pair",
"`FOR n` ... `NEXT` is one loop: every FOR needs a NEXT after it in the same
program part, and every NEXT a FOR. A loop must also stay inside one STL
block or master-control region (or outside all of them).";

    LoopNotOnBus = "E0042", Error, "FOR or NEXT after contacts",
"FOR and NEXT stand on the main bus: no contact drives them. Finish the rung
before FOR, and put conditions inside the loop, or skip the loop with CJ.

    LD X0
    FOR K3      // error";

    LoopTooDeep = "E0043", Error, "loops nested too deep",
"FOR/NEXT loops nest up to 5 levels.";

    JumpAcrossLoop = "E0044", Error, "jump into or out of a loop",
"A CJ inside a loop may jump only to a label in the same loop, and a CJ
outside a loop may not jump into one: the loop's count would be skipped or
left behind. Jump over the whole loop instead.";

    MalformedCsvRow = "E0045", Error, "unreadable row of an instruction-list export",
"An instruction-list export (GX Works2, GX Developer, a step CSV) has one
row per step: fields separated by tabs or commas, quoted or not (step, line
statement, instruction, operand, blank, PI statement, note). This row cannot
be read: a quote is not closed, text follows a closing quote, or it holds an
operand with no instruction above it. Export the program again, or fix the
row.";

    UnknownEncoding = "E0046", Error, "text encoding not recognised",
"Program files are UTF-8 (with or without the byte-order mark EF BB BF) or
UTF-16 with a byte-order mark (FF FE little-endian, as GX Works2 exports,
or FE FF big-endian). The file holds bytes that are not valid in the
encoding its start says, e.g. a Shift-JIS or Latin-1 file without a mark.
Save it as UTF-8 or UTF-16.";

    NotAnFxProgram = "E0047", Error, "an export of another PLC family",
"The export's PLC information names a CPU of another family: a MELSEC-L,
MELSEC-Q or MELSEC iQ-R CPU, or an iQ-F (FX5). Their instruction lists use
other devices (SM400, SD, U\\G with other numbers, hexadecimal X/Y) and other
instructions, so ladderc does not read them as FX programs. ladderc compiles
programs of Mitsubishi FX PLCs (FX1S, FX1N, FX2N, FX3U, FX3G and
compatibles): export the FX project, or port the program.";

    UnreadableExport = "E0048", Error, "a file that looks like an export but is not one ladderc reads",
"Most lines of the file hold several fields separated by commas or tabs,
as an editor's CSV export does, but ladderc could not find the rows of an
instruction list in them (step, line statement, instruction, operand,
...). Rather than reporting every line as broken IL, ladderc reports this
once. Export the program as an instruction list (GX Works2: Project >
Export to CSV file; GX Developer: Write to CSV file), or save it as plain
IL with one instruction per line.";

    PropertySyntax = "E0049", Error, "a line of a property file that cannot be read",
"A property file (`ladderc verify`) has one directive per line: program,
scan-ms, input, init, force, assume, never, always, reach or respond. The
line is none of them, or its expression is not complete.

    never Y0 &                     # error: the expression ends too early
    respond X2 -> !Y0 within       # error: `within` without a number

Expressions combine bits and comparisons of words with `!`, `&`, `|`, `->`
and `<->`; `prev(DEV)`, `rose(DEV)` and `fell(DEV)` look at the previous
scan. A respond property is `respond EXPR1 -> EXPR2 within N`.";

    PropertyDevice = "E0050", Error, "a device a property file names that does not exist",
"The name is not a device of the dialect, or its number is outside its
area, as in a scenario.

    never Y0 & M9000               # error: M goes up to M8511

Devices are named as in scenarios: X0, Y10, M5, S20, TS0/CS3 (contacts),
TN0/CN0 (current values), D0, D10:32 (the pair D11, D10), K4M0, D0.F.";

    PropertyType = "E0051", Error, "a bit used as a word, or a word as a bit",
"A bit stands alone in an expression; a word is compared with a number or
another word. A number given in decimal must lie in the word's signed range
(H numbers give the bits).

    never D0                       # error: compare it: never D0 != 0
    always X0 > 1                  # error: X0 is a bit
    never D0 > 40000               # error: a 16-bit word holds -32768..32767

`T0` and `C0` are the contacts when they stand alone and the current values
in a comparison.";

    PropertyPrevInAssume = "E0052", Error, "`prev`, `rose` or `fell` in an assumption",
"An `assume` line is read on the image before each scan, with the scan's
inputs written: there is no previous scan to look at there.

    assume rose(X0) -> !X1         # error

Say it of the inputs themselves, or state it as a property instead.";

    UndecodableProject = "E0053", Error, "a GX Developer file that cannot be decoded",
"A GX Developer project (the folder with Gppw.gps, its .gps file, or its
Pou/Body/MAIN.wpg) is read from its binary files: the program MAIN.wpg,
the device comments Others/COMMENT.wcd and the parameters param.wpa. One of
them is cut short or holds bytes ladderc cannot read at the offset the
message names: a record whose two length bytes differ, an operand code
ladderc does not know, an instruction code outside the table ladderc reads
(docs/language.md, GX Developer projects), a program longer than 64000
steps, a MAIN.wpg whose size is not the program memory (its NOPs after END
cut short, or not the size param.wpa declares), or a file of another MELSEC
family. Nothing of the project is compiled. Open the project in GX
Developer and save it again, or export the program as an instruction list
(CSV), which ladderc reads as well.";

    NotOnThisCpu = "E0054", Error, "an instruction or device the program's CPU does not have",
"The program names its CPU (`//@ cpu FX2N`, written by ladderc from a GX
Developer project's parameters; or the CPU of the project `import
--to-gx-developer` writes it to), and the instruction or device is not one
that CPU has: the FX2N, FX1N and earlier series have no file registers (R),
no buffer-memory operands (Un\\Gm), no bits of words (D0.1) and none of the
instructions the FX3 series added (MEP, MEF, EMOV, EXP, SCL, ...).

    //@ cpu FX2N
    LD X0
    MOV K1 R0        // error: R is an FX3-series device

Change the CPU in the project's parameters, or rewrite the rung for the CPU.";

    CodeAfterEnd = "W0001", Warning, "code after END",
"Instructions after END are never executed.";

    DoubleCoil = "W0002", Warning, "double coil",
"The device is driven by OUT in more than one place outside STL blocks.
Each OUT takes effect when it executes, so the last one executed wins at
the output refresh; this is usually a mistake. Inside STL blocks, the same
coil in several states is normal and not reported.";

    DrivesNothing = "W0004", Warning, "a program that drives nothing",
"The program is empty, or none of its instructions writes a device (no OUT,
SET, RST, no application instruction): it cannot do anything. A file cut
short by an editor or a failed copy looks like this. `ladderc serve` refuses
such a program for online change unless the upload says it is meant
(`POST /api/program?allow_empty=1`).

    // a file that holds only comments
    // LD X0
    // OUT Y0";

    SystemRelayWrite = "W0003", Warning, "write to a special relay the runtime rewrites",
"SM0-SM3, M8000-M8003, the clock relays M8011-M8014, M8150, M8151 and M8160
are set by the runtime at the start of every scan; writing them lasts only
until then.";
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for Code {
    type Err = ();

    /// Parses `E0001`, `e0001` or `1`-style shorthand is not accepted: codes
    /// are spelled in full.
    fn from_str(text: &str) -> Result<Code, ()> {
        let wanted = text.trim().to_ascii_uppercase();
        Code::ALL.iter().copied().find(|code| code.as_str() == wanted).ok_or(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn codes_are_unique_and_parse_back() {
        let mut seen = HashSet::new();
        for &code in Code::ALL {
            assert!(seen.insert(code.as_str()), "{code} twice");
            assert_eq!(code.as_str().parse::<Code>(), Ok(code));
            assert!(!code.explanation().is_empty());
            let prefix = if code.severity() == Severity::Error { 'E' } else { 'W' };
            assert!(code.as_str().starts_with(prefix), "{code} has the wrong letter");
        }
    }
}
