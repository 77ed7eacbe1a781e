//! Programs for the benchmarks in `benches/`.

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
