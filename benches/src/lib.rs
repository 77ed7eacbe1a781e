//! Programs for the benchmarks in `benches/`.

pub mod heap;
pub mod paired;

use std::fmt::Write;

/// A plant-sized program: `units` copies of a machine section (start/stop
/// with interlock, a timer, a counter, arithmetic, comparisons, an edge, a
/// three-state STL sequence), each on its own devices.
pub fn plant(units: u32) -> String {
    let mut text = String::from("LD M8002\nSET S0\n");
    for u in 0..units {
        let (x, y, m, t, c, d, s) = (u % 32 * 8, u % 32 * 8, u * 8, u % 180, u % 180, u * 8, 10 + u * 3);
        let octal = |n: u32| format!("{n:o}");
        writeln!(
            text,
            "LD X{x0}\nOR Y{y0}\nANI X{x1}\nAND M{m5}\nOUT Y{y0}\n\
             LD Y{y0}\nOUT T{t} K50\nLD T{t}\nOUT C{c} K100\n\
             LDP X{x2}\nINC D{d}\nLD SM0\nADD D{d} K3 D{d1}\nMUL D{d1} K2 D{d2}\n\
             LD> D{d1} K1000\nOR= D{d} K7\nMPS\nAND X{x3}\nOUT M{m0}\nMPP\nANI X{x4}\nOUT M{m1}\n\
             LD M8002\nSET S{s}\nSTL S{s}\nLD SM0\nOUT M{m2}\nLD X{x5}\nSET S{s1}\nSTLE\n\
             STL S{s1}\nLD SM0\nOUT M{m3}\nLD X{x6}\nSET S{s2}\nSTLE\n\
             STL S{s2}\nLD SM0\nOUT M{m4}\nLD X{x7}\nSET S{s}\nSTLE\nLD SM0\nOUT M{m5}",
            x0 = octal(x),
            x1 = octal(x + 1),
            x2 = octal(x + 2),
            x3 = octal(x + 3),
            x4 = octal(x + 4),
            x5 = octal(x + 5),
            x6 = octal(x + 6),
            x7 = octal(x + 7),
            y0 = octal(y),
            m0 = m,
            m1 = m + 1,
            m2 = m + 2,
            m3 = m + 3,
            m4 = m + 4,
            m5 = m + 5,
            d1 = d + 1,
            d2 = d + 2,
            s1 = s + 1,
            s2 = s + 2,
        )
        .expect("writing to a String");
    }
    text
}

/// A deterministic pseudo-random sequence (SplitMix64), so every run and
/// every machine benchmarks the same programs.
struct Sequence(u64);

impl Sequence {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number below `n`.
    fn below(&mut self, n: u32) -> u32 {
        (self.next() % u64::from(n)) as u32
    }
}

/// The most relays a bit-logic program uses: M0..M1023.
pub const BIT_LOGIC_RELAYS: u32 = 1024;

/// A straight-line bit-logic program of about `instructions` IL
/// instructions (contacts on X, Y and M, blocks, OUT/SET/RST of M and Y; the
/// kind of program the IL→C→gcc route is usually shown with), as IL and as
/// the C a translator would write for it: one byte per bit in global
/// arrays, the scan a `noinline` function. The C reads and
/// writes the same bytes the compiled program does, so after the same scans
/// both leave the same Y and M.
pub struct BitLogic {
    pub il: String,
    pub c: String,
    pub instructions: usize,
}

/// `relays` (at most `BIT_LOGIC_RELAYS`) is how many M relays the rungs
/// share: few relays means values written by one rung are read by the next
/// ones, as in real interlocking logic.
pub fn bit_logic(instructions: usize, relays: u32, seed: u64) -> BitLogic {
    let relays = relays.clamp(1, BIT_LOGIC_RELAYS);
    let mut random = Sequence(seed);
    let mut il = String::new();
    // Globals, as LDmicro and matiec's OpenPLC runtime keep their
    // variables (hidden: a shared library reaches them without the GOT,
    // as a static link would); accessors for the bench.
    let mut c = String::from(
        "#include <stdint.h>\n\
         #define HIDDEN __attribute__((visibility(\"hidden\")))\n\
         HIDDEN uint8_t x[256], y[256], m[1024];\n\
         uint8_t *image_x(void) { return x; }\n\
         uint8_t *image_y(void) { return y; }\n\
         uint8_t *image_m(void) { return m; }\n\
         __attribute__((noinline)) void scan(void) {\n\
         uint8_t a, b;\n",
    );
    let mut count = 0;
    // A contact: (IL operand, C expression).
    let contact = |random: &mut Sequence| -> (String, String) {
        match random.below(10) {
            0..=2 => {
                let n = random.below(256);
                (format!("X{n:o}"), format!("x[{n}]"))
            }
            3 => {
                let n = random.below(256);
                (format!("Y{n:o}"), format!("y[{n}]"))
            }
            _ => {
                let n = random.below(relays);
                (format!("M{n}"), format!("m[{n}]"))
            }
        }
    };
    while count < instructions {
        let (first, first_c) = contact(&mut random);
        if random.below(4) == 0 {
            writeln!(il, "LDI {first}").expect("String");
            writeln!(c, "a = !{first_c};").expect("String");
        } else {
            writeln!(il, "LD {first}").expect("String");
            writeln!(c, "a = {first_c};").expect("String");
        }
        count += 1;
        for _ in 0..1 + random.below(5) {
            let (operand, operand_c) = contact(&mut random);
            let (mnemonic, expression) = match random.below(8) {
                0..=3 => ("AND", format!("a = a & {operand_c};")),
                4 => ("ANI", format!("a = a & !{operand_c};")),
                5 | 6 => ("OR", format!("a = a | {operand_c};")),
                _ => ("ORI", format!("a = a | !{operand_c};")),
            };
            writeln!(il, "{mnemonic} {operand}").expect("String");
            writeln!(c, "{expression}").expect("String");
            count += 1;
        }
        if random.below(5) == 0 {
            // A block of two contacts joined by ORB or ANB.
            let (x, x_c) = contact(&mut random);
            let (y, y_c) = contact(&mut random);
            let (join, op) = if random.below(2) == 0 {
                ("ORB", '|')
            } else {
                ("ANB", '&')
            };
            writeln!(il, "LD {x}\nAND {y}\n{join}").expect("String");
            writeln!(c, "b = {x_c} & {y_c};\na = a {op} b;").expect("String");
            count += 3;
        }
        let (area, area_c, n) = if random.below(6) == 0 {
            ("Y", "y", random.below(256))
        } else {
            ("M", "m", random.below(relays))
        };
        let name = if area == "Y" {
            format!("Y{n:o}")
        } else {
            format!("M{n}")
        };
        match random.below(12) {
            0 => {
                writeln!(il, "SET {name}").expect("String");
                writeln!(c, "if (a) {area_c}[{n}] = 1;").expect("String");
            }
            1 => {
                writeln!(il, "RST {name}").expect("String");
                writeln!(c, "if (a) {area_c}[{n}] = 0;").expect("String");
            }
            _ => {
                writeln!(il, "OUT {name}").expect("String");
                writeln!(c, "{area_c}[{n}] = a;").expect("String");
            }
        }
        count += 1;
    }
    c.push_str("}\n");
    BitLogic {
        il,
        c,
        instructions: count,
    }
}
