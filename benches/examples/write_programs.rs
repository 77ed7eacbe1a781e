fn main() {
    let n: usize = std::env::args().nth(1).unwrap().parse().unwrap();
    let relays: u32 = std::env::args().nth(2).map_or(1024, |r| r.parse().unwrap());
    let p = ladderc_benches::bit_logic(n, relays, 1);
    std::fs::write(format!("/tmp/bl{n}_{relays}.il"), &p.il).unwrap();
    std::fs::write(format!("/tmp/bl{n}_{relays}.c"), &p.c).unwrap();
    let t = ladderc_benches::plant((n / 47) as u32);
    std::fs::write(format!("/tmp/plant{n}.il"), &t).unwrap();
}
