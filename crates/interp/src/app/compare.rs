//! Comparisons: CMP, ZCP.

/// S1 > S2, S1 = S2, S1 < S2.
pub fn cmp([a, b]: [i64; 2]) -> [bool; 3] {
    [a > b, a == b, a < b]
}

/// S below, inside, above the zone [S1, S2]. A reversed zone (S1 > S2) is
/// read as the single value S1, as an FX does.
pub fn zcp([low, high, s]: [i64; 3]) -> [bool; 3] {
    let high = high.max(low);
    [s < low, (low..=high).contains(&s), s > high]
}
