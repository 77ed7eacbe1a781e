//! The dispatch of application instructions, written once for both
//! engines: the reference interpreter (`ladder-interp`, `app/mod.rs`) and
//! the lowering (`ladder-ir`, `lower/app/mod.rs`) each expand it with their
//! own `Step` and their own kernel modules (`moves`, `arithmetic`, ...,
//! named alike in both, with the same signatures), so which kernel an
//! instruction runs and which operand plays which role (the pulse
//! instructions' frequency, amount, ...) is decided here, and a new
//! instruction is one arm that the compiler asks for in both crates at once.
//! Its kernels stay written twice on purpose: the differential test holds
//! one against the other.
//!
//! `app_dispatch!(args, step, run, flags)`: `args` the `&AppArgs`, `step`
//! the engine's operand step, `run` its `Execution`, `flags` the special
//! relays the instruction declares it writes.

#[macro_export]
macro_rules! app_dispatch {
    ($args:expr, $step:ident, $run:ident, $flags:ident) => {{
        use ::ladder_runtime::hsc::HscCompare;
        use ::ladder_runtime::pulse::PulseKind;
        use ::ladder_runtime::real::RealFunction;
        use $crate::isa::AppArgs;
        use $crate::program::PulseOperands;
        match $args {
            AppArgs::Mov { s, d } => $step.map([s], d, moves::mov),
            AppArgs::BlockMov { s, d, n } => moves::block_move($step, s, d, n),
            AppArgs::FillMov { s, d, n } => moves::fill_move($step, s, d, n),
            AppArgs::Add { s1, s2, d } => $step.map_flags([s1, s2], d, $flags, arithmetic::add),
            AppArgs::Sub { s1, s2, d } => $step.map_flags([s1, s2], d, $flags, arithmetic::sub),
            AppArgs::Mul { s1, s2, d } => $step.map_double([s1, s2], d, arithmetic::mul),
            AppArgs::Div { s1, s2, d } => $step.map_double([s1, s2], d, arithmetic::div),
            AppArgs::Inc { d } => $step.modify(d, arithmetic::inc),
            AppArgs::Dec { d } => $step.modify(d, arithmetic::dec),
            AppArgs::Cmp { s1, s2, d } => $step.map_bits([s1, s2], d, compare::cmp),
            AppArgs::ZoneCmp { s1, s2, s, d } => $step.map_bits([s1, s2, s], d, compare::zcp),
            AppArgs::Neg { d } => $step.modify(d, arithmetic::neg),
            AppArgs::Sqr { s, d } => $step.map_flags([s], d, $flags, arithmetic::sqr),
            AppArgs::Wand { s1, s2, d } => $step.map([s1, s2], d, logic::wand),
            AppArgs::Wor { s1, s2, d } => $step.map([s1, s2], d, logic::wor),
            AppArgs::Wxor { s1, s2, d } => $step.map([s1, s2], d, logic::wxor),
            AppArgs::Cml { s, d } => $step.map([s], d, logic::cml),
            AppArgs::Bon { s, n, d } => $step.map_bit([s, n], d, logic::bon),
            AppArgs::Sum { s, d } => $step.map_flags([s], d, $flags, logic::sum),
            AppArgs::Swap { d } => $step.modify(d, convert::swap),
            AppArgs::Encode { s, n, d } => convert::encode($step, s, n, d),
            AppArgs::Decode { s, n, d } => convert::decode($step, s, n, d),
            AppArgs::BytesToWords { s, d, n } => convert::bytes($step, s, d, n, false),
            AppArgs::WordsToBytes { s, d, n } => convert::bytes($step, s, d, n, true),
            AppArgs::Distribute { s, d, n } => convert::distribute($step, s, d, n),
            AppArgs::Unite { s, d, n } => convert::unite($step, s, d, n),
            AppArgs::OctalMove { s, d } => moves::octal_move($step, s, d),
            AppArgs::ZoneReset { d1, d2 } => zone::reset($step, d1, d2),
            AppArgs::ZoneSet { d1, d2 } => zone::set($step, d1, d2),
            AppArgs::Max { s1, s2, d } => table::extreme($step, s1, s2, d, true),
            AppArgs::Min { s1, s2, d } => table::extreme($step, s1, s2, d, false),
            AppArgs::Limit { s1, s2, s3, d } => $step.map([s1, s2, s3], d, table::limit),
            AppArgs::Mean { s, d, n } => table::mean($step, s, d, n),
            AppArgs::Wsum { s, d, n } => table::sum($step, s, d, n),
            AppArgs::Sort { s, n1, n2, d, n3 } => table::sort($step, $run, [s, n1, n2, d, n3], false),
            AppArgs::Sort2 { s, n1, n2, d, n3 } => table::sort($step, $run, [s, n1, n2, d, n3], true),
            AppArgs::Bcc { s1, s2, s3, d } => check::block_check($step, s1, s2, s3, d),
            AppArgs::Crc { s, d, n } => check::crc($step, s, d, n),
            AppArgs::Ans { s, n, d } => alarm::set($step, $run, s, n, d),
            AppArgs::Anr {} => alarm::reset($step),
            AppArgs::Xch { d1, d2 } => moves::exchange($step, d1, d2),
            AppArgs::Alt { d } => logic::alternate($step, d),
            AppArgs::Bcd { s, d } => $step.map([s], d, convert::bcd),
            AppArgs::Bin { s, d } => $step.map([s], d, convert::bin),
            AppArgs::Ror { d, n } => shift::rotate($step, d, n, true),
            AppArgs::Rol { d, n } => shift::rotate($step, d, n, false),
            AppArgs::ShiftRight { s, d, n1, n2 } => shift::shift_bits($step, s, d, n1, n2, false),
            AppArgs::ShiftLeft { s, d, n1, n2 } => shift::shift_bits($step, s, d, n1, n2, true),
            AppArgs::RealCmp { s1, s2, d } => float::compare($step, &[s1, s2], d),
            AppArgs::RealZoneCmp { s1, s2, s, d } => float::compare($step, &[s1, s2, s], d),
            AppArgs::RealMov { s, d } => float::map($step, [s], d, $flags, float::mov),
            AppArgs::RealAdd { s1, s2, d } => float::map($step, [s1, s2], d, $flags, float::add),
            AppArgs::RealSub { s1, s2, d } => float::map($step, [s1, s2], d, $flags, float::sub),
            AppArgs::RealMul { s1, s2, d } => float::map($step, [s1, s2], d, $flags, float::mul),
            AppArgs::RealDiv { s1, s2, d } => float::map($step, [s1, s2], d, $flags, float::div),
            AppArgs::RealSqr { s, d } => float::map($step, [s], d, $flags, float::sqr),
            AppArgs::RealNeg { d } => float::neg($step, d),
            AppArgs::Flt { s, d } => float::flt($step, s, d),
            AppArgs::Int { s, d } => float::int($step, s, d, $flags),
            AppArgs::RealToDecimal { s, d } => float::to_decimal($step, s, d),
            AppArgs::DecimalToReal { s, d } => float::from_decimal($step, s, d),
            AppArgs::Sin { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Sin)),
            AppArgs::Cos { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Cos)),
            AppArgs::Tan { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Tan)),
            AppArgs::Asin { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Asin)),
            AppArgs::Acos { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Acos)),
            AppArgs::Atan { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Atan)),
            AppArgs::Rad { s, d } => float::map($step, [s], d, $flags, float::angle(true)),
            AppArgs::Deg { s, d } => float::map($step, [s], d, $flags, float::angle(false)),
            AppArgs::Exp { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Exp)),
            AppArgs::Loge { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Ln)),
            AppArgs::Log10 { s, d } => float::map($step, [s], d, $flags, float::apply(RealFunction::Log10)),
            AppArgs::Trd { d } => clock::read($step, d),
            AppArgs::Twr { s } => clock::write($step, s),
            AppArgs::Tcmp { s1, s2, s3, s, d } => clock::compare($step, [s1, s2, s3], s, d),
            AppArgs::Tzcp { s1, s2, s, d } => clock::zone($step, s1, s2, s, d),
            AppArgs::Tadd { s1, s2, d } => clock::add($step, s1, s2, d, false, $flags),
            AppArgs::Tsub { s1, s2, d } => clock::add($step, s1, s2, d, true, $flags),
            AppArgs::Htos { s, d } => clock::to_seconds($step, s, d),
            AppArgs::Stoh { s, d } => clock::to_time($step, s, d),
            AppArgs::Hour { s, d1, d2 } => clock::hour($step, $run.job, s, d1, d2),
            AppArgs::Ser { s1, s2, d, n } => handy::search($step, s1, s2, d, n),
            AppArgs::Absd { s1, s2, d, n } => handy::absolute_drum($step, s1, s2, d, n),
            AppArgs::Incd { s1, s2, d, n } => handy::incremental_drum($step, $run, s1, s2, d, n),
            AppArgs::Ttmr { d, n } => handy::teaching_timer($step, $run, d, n),
            AppArgs::Stmr { s, m, d } => handy::special_timer($step, $run, s, m, d),
            AppArgs::Ramp { s1, s2, d, n } => handy::ramp($step, $run, s1, s2, d, n),
            AppArgs::Segd { s, d } => handy::segment_decode($step, s, d),
            AppArgs::Segl { s, d, n } => handy::segment_latch($step, $run, s, d, n),
            AppArgs::Asci { s, d, n } => handy::ascii($step, s, d, n),
            AppArgs::Hex { s, d, n } => handy::hex($step, s, d, n),
            AppArgs::Ccd { s, d, n } => handy::check_code($step, s, d, n),
            AppArgs::Hscs { s1, s2, d } => highspeed::compare($step, $run, HscCompare::Set, &[s1], s2, d),
            AppArgs::Hscr { s1, s2, d } => highspeed::compare($step, $run, HscCompare::Reset, &[s1], s2, d),
            AppArgs::Hsz { s1, s2, s, d } => highspeed::compare($step, $run, HscCompare::Zone, &[s1, s2], s, d),
            AppArgs::Spd { s1, s2, d } => highspeed::speed($step, s1, s2, d),
            AppArgs::Plsy { s1, s2, d } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Plsy, d).frequency(s1).amount(s2),
            ),
            AppArgs::Plsr { s1, s2, s3, d } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Plsr, d).frequency(s1).amount(s2).ramp(s3),
            ),
            AppArgs::Plsv { s, d1, d2 } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Plsv, d1).frequency(s).direction(d2),
            ),
            AppArgs::Drvi { s1, s2, d1, d2 } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Drvi, d1)
                    .amount(s1)
                    .frequency(s2)
                    .direction(d2),
            ),
            AppArgs::Drva { s1, s2, d1, d2 } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Drva, d1)
                    .amount(s1)
                    .frequency(s2)
                    .direction(d2),
            ),
            AppArgs::Zrn { s1, s2, s3, d } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Zrn, d)
                    .frequency(s1)
                    .creep(s2)
                    .near_point(s3),
            ),
            AppArgs::Dszr { s1, s2, d1, d2 } => highspeed::pulse(
                $step,
                $run,
                &PulseOperands::new(PulseKind::Dszr, d1)
                    .near_point(s1)
                    .zero_signal(s2)
                    .direction(d2),
            ),
            AppArgs::Pwm { s1, s2, d } => highspeed::pulse_width($step, $run, s1, s2, d),
            AppArgs::From { m1, m2, d, n } => module::transfer($step, m1, m2, d, n, true),
            AppArgs::To { m1, m2, s, n } => module::transfer($step, m1, m2, s, n, false),
            AppArgs::Pid { s1, s2, s3, d } => pid::pid($step, $run, s1, s2, s3, d),
        }
    }};
}
