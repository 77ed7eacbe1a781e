//! The portable helpers a generated file starts with — only those its code
//! calls (as wasm2c does): Clang rejects unused `static` functions under
//! `-Wall -Werror`, and a reader should not wade through sixty helpers to
//! find the four a traffic light uses.
//!
//! Each helper is a named piece with the pieces it calls; `prelude_for`
//! takes the closure of the names the code mentions and writes them in the
//! table's order, each group after its comment.

/// Always first: the headers and the image type.
const HEADER: &str = "#include <stdint.h>
#include <string.h>
#include <math.h>

/* Floating point: every IR operation is a statement of its own, so no
   compiler fuses a multiply and an add within one expression; GCC in its
   GNU modes also fuses across statements: compile with -std=c99 (or
   -ffp-contract=off), as the IEEE results of the reference need. */

typedef struct LadderMemory LadderMemory;
";

/// A group of helpers under one comment.
struct Group {
    comment: &'static str,
    pieces: Vec<Piece>,
}

/// One helper: its name, its C text, and the helpers it calls.
struct Piece {
    name: String,
    text: String,
    needs: Vec<String>,
}

fn piece(name: &str, text: &str) -> Piece {
    Piece {
        name: name.to_string(),
        text: text.to_string(),
        needs: Vec::new(),
    }
}

fn groups() -> Vec<Group> {
    let mut groups = vec![
        Group {
            comment: "/* The image is addressed in bytes at the runtime's layout offsets; loads
   and stores go through memcpy (no alignment or aliasing assumptions;
   compilers turn them into plain moves). */",
            pieces: vec![
                piece(
                    "ld_load16",
                    "static inline int16_t ld_load16(const uint8_t *p) { int16_t v; memcpy(&v, p, 2); return v; }",
                ),
                piece(
                    "ld_load32",
                    "static inline int32_t ld_load32(const uint8_t *p) { int32_t v; memcpy(&v, p, 4); return v; }",
                ),
                piece(
                    "ld_store16",
                    "static inline void ld_store16(uint8_t *p, int16_t v) { memcpy(p, &v, 2); }",
                ),
                piece(
                    "ld_store32",
                    "static inline void ld_store32(uint8_t *p, int32_t v) { memcpy(p, &v, 4); }",
                ),
            ],
        },
        Group {
            comment: "/* A run-time index, as an unsigned minimum: a negative one is huge and
   clamps too. */",
            pieces: vec![piece(
                "ld_clamp",
                "static inline uint32_t ld_clamp(int32_t index, uint32_t last) {
    uint32_t u = (uint32_t)index;
    return u < last ? u : last;
}",
            )],
        },
        Group {
            comment: "/* Floating-point values from and to their bits. */",
            pieces: vec![
                piece(
                    "ld_f32_bits",
                    "static inline float ld_f32_bits(uint32_t bits) { float f; memcpy(&f, &bits, 4); return f; }",
                ),
                piece(
                    "ld_f64_bits",
                    "static inline double ld_f64_bits(uint64_t bits) { double f; memcpy(&f, &bits, 8); return f; }",
                ),
                piece(
                    "ld_f32_to_i32_bits",
                    "static inline int32_t ld_f32_to_i32_bits(float f) { int32_t v; memcpy(&v, &f, 4); return v; }",
                ),
                piece(
                    "ld_f64_to_i64_bits",
                    "static inline int64_t ld_f64_to_i64_bits(double f) { int64_t v; memcpy(&v, &f, 8); return v; }",
                ),
            ],
        },
    ];
    for width in [8u32, 16, 32, 64] {
        groups.push(integer_group(width));
    }
    groups
}

/// The integer operations of one width. Two's-complement arithmetic on
/// N-bit values, wrapping, without C's undefined signed overflow.
fn integer_group(n: u32) -> Group {
    let (s, u, a) = match n {
        64 => ("int64_t", "uint64_t", "uint64_t"),
        _ => (
            ["int8_t", "int16_t", "int32_t"][(n / 16) as usize],
            ["uint8_t", "uint16_t", "uint32_t"][(n / 16) as usize],
            "uint32_t",
        ),
    };
    let (smin, smax) = (format!("INT{n}_MIN"), format!("INT{n}_MAX"));
    let fill = |text: &str| {
        text.replace("{N}", &n.to_string())
            .replace("{S}", s)
            .replace("{U}", u)
            .replace("{A}", a)
            .replace("{SMIN}", &smin)
            .replace("{SMAX}", &smax)
    };
    let templates: [(&str, &str, &[&str]); 15] = [
        (
            "s",
            "static inline {S} ld_s{N}({A} a) {
    {U} u = ({U})a;
    return u <= ({U}){SMAX} ? ({S})u : ({S})(({S})(u - ({U}){SMAX} - 1u) + {SMIN});
}",
            &[],
        ),
        (
            "add",
            "static inline {S} ld_add{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})a + ({A})b)); }",
            &["s"],
        ),
        (
            "sub",
            "static inline {S} ld_sub{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})a - ({A})b)); }",
            &["s"],
        ),
        (
            "mul",
            "static inline {S} ld_mul{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})a * ({A})b)); }",
            &["s"],
        ),
        (
            "div",
            "static inline {S} ld_div{N}({S} a, {S} b) {
    if (b == 0) return 0;
    if (a == {SMIN} && b == -1) return {SMIN};
    return ({S})(a / b);
}",
            &[],
        ),
        (
            "rem",
            "static inline {S} ld_rem{N}({S} a, {S} b) {
    if (b == 0 || b == -1) return 0;
    return ({S})(a % b);
}",
            &[],
        ),
        (
            "and",
            "static inline {S} ld_and{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})a & ({A})b)); }",
            &["s"],
        ),
        (
            "or",
            "static inline {S} ld_or{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})a | ({A})b)); }",
            &["s"],
        ),
        (
            "xor",
            "static inline {S} ld_xor{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})a ^ ({A})b)); }",
            &["s"],
        ),
        (
            "shl",
            "static inline {S} ld_shl{N}({S} a, {S} b) { return ld_s{N}(({A})(({A})({U})a << (({A})b & ({N} - 1)))); }",
            &["s"],
        ),
        (
            "ushr",
            "static inline {S} ld_ushr{N}({S} a, {S} b) { return ld_s{N}(({A})(({U})a >> (({A})b & ({N} - 1)))); }",
            &["s"],
        ),
        (
            "sshr",
            "static inline {S} ld_sshr{N}({S} a, {S} b) {
    unsigned n = (unsigned)(({A})b & ({N} - 1));
    return a < 0 ? ({S})~({S})(({S})~a >> n) : ({S})(a >> n);
}",
            &[],
        ),
        (
            "popcnt",
            "static inline {S} ld_popcnt{N}({S} a) {
    {U} u = ({U})a;
    {S} count = 0;
    while (u) { count = ({S})(count + ({S})(u & 1u)); u = ({U})(u >> 1); }
    return count;
}",
            &[],
        ),
        (
            "clz",
            "static inline {S} ld_clz{N}({S} a) {
    {U} u = ({U})a;
    {S} count = 0;
    {U} top = ({U})(({U})1 << ({N} - 1));
    while (count < {N} && !(u & top)) { count = ({S})(count + 1); u = ({U})(u << 1); }
    return count;
}",
            &[],
        ),
        (
            "sat",
            "/* Float to integer, saturating: NaN is 0. */
static inline {S} ld_sat{N}(double x) {
    if (x != x) return 0;
    if (x <= (double){SMIN}) return {SMIN};
    if (x >= -(double){SMIN}) return {SMAX};
    return ({S})x;
}",
            &[],
        ),
    ];
    let mut pieces: Vec<Piece> = templates
        .iter()
        .map(|(op, text, needs)| Piece {
            name: format!("ld_{op}{n}"),
            text: fill(text),
            needs: needs.iter().map(|need| format!("ld_{need}{n}")).collect(),
        })
        .collect();
    pieces.push(Piece {
        name: format!("ld_isqrt{n}"),
        text: fill("static inline {S} ld_isqrt{N}({S} a) { return ld_sat{N}(sqrt((double)a)); }"),
        needs: vec![format!("ld_sat{n}")],
    });
    Group {
        comment: if n == 8 {
            "/* Two's-complement integer arithmetic on N-bit values (ld_<op>N),
   wrapping, without the undefined behaviour of signed overflow in C: the
   arithmetic is done on an unsigned type and brought back by ld_sN, which
   maps the unsigned N-bit value to the signed one without an
   implementation-defined conversion. Division by zero gives 0 and the one
   overflowing division (MIN / -1) gives MIN, where machine code would
   trap; the compiler never emits either. Shift amounts are taken modulo
   N, as machine shifts do. */"
        } else {
            ""
        },
        pieces,
    }
}

/// Whether `code` calls `name` (the name followed by an opening parenthesis,
/// not the tail of a longer name).
fn calls(code: &str, name: &str) -> bool {
    let pattern = format!("{name}(");
    code.match_indices(&pattern).any(|(at, _)| {
        !code[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
    })
}

/// The prelude for `code`: the header and every helper `code` calls, with
/// the helpers those call.
pub fn prelude_for(code: &str) -> String {
    let groups = groups();
    let all: Vec<&Piece> = groups.iter().flat_map(|g| &g.pieces).collect();
    let mut wanted: Vec<&str> = all
        .iter()
        .filter(|p| calls(code, &p.name))
        .map(|p| p.name.as_str())
        .collect();
    let mut next = 0;
    while next < wanted.len() {
        let name = wanted[next];
        next += 1;
        if let Some(piece) = all.iter().find(|p| p.name == name) {
            for need in &piece.needs {
                if !wanted.contains(&need.as_str()) {
                    wanted.push(need);
                }
            }
        }
    }
    // The integer groups share the first one's comment: write it once,
    // before the first integer helper written.
    let integer_comment = groups
        .iter()
        .map(|g| g.comment)
        .find(|c| c.contains("Two's-complement"));
    let mut integer_comment_written = false;
    let mut out = String::from(HEADER);
    for group in &groups {
        let used: Vec<&Piece> = group
            .pieces
            .iter()
            .filter(|p| wanted.contains(&p.name.as_str()))
            .collect();
        if used.is_empty() {
            continue;
        }
        out.push('\n');
        let comment = if group.comment.is_empty() || group.comment.contains("Two's-complement") {
            if integer_comment_written {
                ""
            } else {
                integer_comment_written = true;
                integer_comment.unwrap_or("")
            }
        } else {
            group.comment
        };
        if !comment.is_empty() {
            out.push_str(comment);
            out.push('\n');
        }
        for piece in used {
            out.push_str(&piece.text);
            out.push('\n');
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_called_helpers_and_what_they_call_are_written() {
        let prelude = prelude_for("x = ld_add16(a, b); y = ld_load16(m + 2); z = ld_isqrt32(q);");
        assert!(prelude.contains("ld_add16("));
        assert!(
            prelude.contains("static inline int16_t ld_s16("),
            "ld_add16 calls ld_s16"
        );
        assert!(prelude.contains("ld_sat32("), "ld_isqrt32 calls ld_sat32");
        assert!(prelude.contains("ld_load16("));
        assert!(!prelude.contains("ld_sub16"));
        assert!(!prelude.contains("ld_store16"));
        assert!(!prelude.contains("ld_add8"));
        assert_eq!(prelude.matches("Two's-complement").count(), 1);
    }

    #[test]
    fn a_name_inside_a_longer_name_is_not_a_call() {
        assert!(!calls("my_ld_add16(a)", "ld_add16"));
        assert!(calls("(ld_add16(a, b))", "ld_add16"));
        assert!(!calls("ld_add160(a)", "ld_add16"));
    }

    #[test]
    fn every_helper_is_written_when_every_helper_is_called() {
        let groups = groups();
        let code: String = groups
            .iter()
            .flat_map(|g| &g.pieces)
            .map(|p| format!("{}();\n", p.name))
            .collect();
        let prelude = prelude_for(&code);
        for piece in groups.iter().flat_map(|g| &g.pieces) {
            assert!(prelude.contains(&piece.text), "{}", piece.name);
        }
    }
}
