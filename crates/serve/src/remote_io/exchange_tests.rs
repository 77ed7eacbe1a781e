//! Tests of the handoff: a poll reaches the input image, outputs reach the
//! poller only when a scan changed them, a lost device holds or clears.

use super::super::config::parse;
use super::*;

const FILE: &str = r#"
[[device]]
tcp = "127.0.0.1:1502"
on_loss = "clear"
status = "M10"
errors = "D10"
[[device.input]]
discrete_inputs = 0
count = 3
to = "X0"
[[device.input]]
input_registers = 0
count = 1
to = "D0"
[[device.output]]
coils = 0
count = 2
from = "Y0"
[[device.output]]
holding_registers = 0
count = 1
from = "D1"
"#;

#[test]
fn a_poll_and_a_loss_reach_the_scan_and_outputs_go_out_on_change() {
    let io = parse(FILE).unwrap();
    let exchange = Exchange::new(&io.devices, Duration::from_millis(10));
    let slot = &exchange.slots[0];
    slot.publish(&[true, false, true], &[0xFFFF], 0);
    {
        let inputs = lock(&slot.inputs);
        assert_eq!(inputs.bits, [true, false, true]);
        assert!(inputs.connected);
    }
    let mut memory = ladder_runtime::Memory::new_boxed();
    let mut taken = Outputs::sized(&slot.device);
    assert!(!slot.outputs_since(0, &mut taken), "no scan yet");
    exchange.from_image(&memory);
    assert!(slot.outputs_since(0, &mut taken), "the first scan's outputs");
    let generation = taken.generation;
    exchange.from_image(&memory);
    assert!(!slot.outputs_since(generation, &mut taken), "nothing changed");
    memory.image().write_device(Place::Bit(BitArea::Y, 1), Width::Single, 1);
    memory
        .image()
        .write_device(Place::Word(WordArea::D, 1), Width::Single, -2);
    exchange.from_image(&memory);
    assert!(slot.outputs_since(generation, &mut taken));
    assert_eq!(
        (taken.bits.as_slice(), taken.words.as_slice()),
        ([false, true].as_slice(), [0xFFFE].as_slice())
    );
    slot.fail("refused".into(), false);
    assert!(lock(&slot.inputs).connected, "one failure within the retries");
    slot.fail("refused".into(), true);
    let inputs = lock(&slot.inputs).clone();
    assert_eq!((inputs.connected, inputs.errors), (false, 2));
    assert_eq!(inputs.bits, [false; 3], "cleared");
    assert_eq!(slot.state().losses, 1);
}

#[test]
fn the_error_count_saturates() {
    assert_eq!(saturated(40_000), 32_767);
    assert_eq!(saturated(5), 5);
}

#[test]
fn keep_alives_stop_when_the_scan_thread_stops_handing_outputs_over() {
    let io = parse(FILE).unwrap();
    let exchange = Exchange::new(&io.devices, Duration::from_millis(10));
    let beat = &exchange.slots[0].beat;
    assert!(!beat.alive(), "no scan yet");
    exchange.from_image(&ladder_runtime::Memory::new_boxed());
    assert!(beat.alive(), "a scan just handed the outputs over");
    // Three scan periods and more without a hand-off: stalled.
    std::thread::sleep(Duration::from_millis(40));
    assert!(!beat.alive(), "stalled");
    exchange.from_image(&ladder_runtime::Memory::new_boxed());
    assert!(beat.alive(), "beating again");
}

#[test]
fn the_units_of_one_serial_line_share_a_link_and_its_signal() {
    let io = parse(
        "[[device]]\nrtu = \"/dev/ttyS9:9600,8N1\"\nunit = 1\n\
         [[device]]\ntcp = \"127.0.0.1:502\"\n\
         [[device]]\nrtu = \"/dev/ttyS9:9600,8N1\"\nunit = 2\n",
    )
    .unwrap();
    let exchange = Exchange::new(&io.devices, Duration::from_millis(10));
    let links = exchange.links();
    let names: Vec<Vec<&str>> = links
        .iter()
        .map(|link| link.iter().map(|slot| slot.device.name.as_str()).collect())
        .collect();
    assert_eq!(names, [vec!["device1", "device3"], vec!["device2"]]);
    assert!(Arc::ptr_eq(&exchange.slots[0].changed, &exchange.slots[2].changed));
    assert!(!Arc::ptr_eq(&exchange.slots[0].changed, &exchange.slots[1].changed));
}
