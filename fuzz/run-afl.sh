#!/usr/bin/env bash
# Runs AFL++ on one ladderc fuzz target on the stable toolchain.
#   fuzz/run-afl.sh TARGET SECONDS      (TARGET: front_end | scenario | properties | pipeline | modbus | modbus_rtu | melsec | http | gx_developer)
# Seeds come from the repository's programs and scenarios; findings land in
# target/afl/TARGET/default/crashes.
set -euo pipefail
cd "$(dirname "$0")"
target=${1:?target: front_end, scenario, properties, pipeline, modbus, modbus_rtu, melsec, http or gx_developer}
seconds=${2:-600}
command -v cargo-afl >/dev/null || cargo install --locked cargo-afl
cargo afl build --release --features afl --bin "afl_$target"
seeds=target/afl/$target/seeds
mkdir -p "$seeds"
if [ "$target" = modbus ]; then
    # A flags byte (bit 0: writes allowed), then frames: reads, writes,
    # a bad coil value, a multiple write, an unknown function.
    printf '\x01\x00\x01\x00\x00\x00\x06\x01\x03\x00\x00\x00\x0a' > "$seeds/read"
    printf '\x01\x00\x02\x00\x00\x00\x06\x01\x05\x00\x00\xff\x00\x00\x03\x00\x00\x00\x06\x01\x05\x00\x00\x12\x34' > "$seeds/coils"
    printf '\x00\x00\x04\x00\x00\x00\x0b\x01\x10\x00\x00\x00\x02\x04\x00\x01\x00\x02' > "$seeds/registers"
    printf '\x01\x00\x05\x00\x00\x00\x08\x01\x0f\x4e\x20\x00\x09\x02\xff\x01' > "$seeds/multiple"
    printf '\x01\x00\x06\x00\x00\x00\x03\x01\x2b\x0e' > "$seeds/unknown"
elif [ "$target" = modbus_rtu ]; then
    # A flags byte, then frames each after its length: a read, a bad CRC,
    # a broadcast write.
    printf '\x01\x08\x01\x03\x00\x00\x00\x01\x84\x0a\x08\x01\x03\x00\x00\x00\x01\x00\x00' > "$seeds/read"
    printf '\x01\x08\x00\x06\x00\x00\x00\x07\xc9\xd9' > "$seeds/broadcast"
elif [ "$target" = melsec ]; then
    # A flags byte (bit 0: writes allowed), then frames of each kind: 1E
    # binary and ASCII, 3E binary and ASCII, 4E binary.
    printf '\x01\x00\xff\x0a\x00\x64\x00\x00\x00\x20\x4d\x08\x00' > "$seeds/1e"
    printf '\x0101FF000A4420000000640200' > "$seeds/1e_ascii"
    printf '\x01\x50\x00\x00\xff\xff\x03\x00\x0c\x00\x10\x00\x01\x04\x00\x00\x64\x00\x00\xa8\x03\x00' > "$seeds/3e"
    printf '\x01500000FF03FF000018001004010000D*0001000003' > "$seeds/3e_ascii"
    printf '\x01\x54\x00\x34\x12\x00\x00\x00\xff\xff\x03\x00\x0c\x00\x10\x00\x01\x04\x01\x00\x00\x00\x00\x9c\x08\x00' > "$seeds/4e"
elif [ "$target" = http ]; then
    # The first line is the method and the path; the rest is the body.
    printf 'GET /api/devices?watch=Y0..Y7,D10:32,D0:hex' > "$seeds/devices"
    printf 'POST /api/set\n{"device": "D20:32", "value": 100000}' > "$seeds/set"
    printf 'POST /api/force\n{"device": "X0", "value": "on"}' > "$seeds/force"
    printf 'POST /api/control\n{"action": "step", "scans": 3}' > "$seeds/control"
    printf 'POST /api/breakpoints\n{"condition": "D0 > 100"}' > "$seeds/breakpoint"
    printf 'POST /api/program?allow_empty=1\nLD X0\nOUT Y0\n' > "$seeds/program"
    printf 'GET /api/ladder/state?rungs=0,1,2' > "$seeds/ladder"
    printf 'GET /api/stats' > "$seeds/stats"
elif [ "$target" = gx_developer ]; then
    dir=../testsuite/gxdeveloper/3floor_elevator
    { printf '\000'; cat "$dir/Pou/Body/MAIN.wpg"; } > "$seeds/main"
    { printf '\001'; cat "$dir/Others/COMMENT.wcd"; } > "$seeds/comments"
    { printf '\002'; cat "$dir/param.wpa"; } > "$seeds/parameters"
elif [ "$target" = properties ]; then
    find ../testsuite/properties -name '*.prop' -size -4k | while read -r f; do
        cp "$f" "$seeds/$(echo "$f" | tr '/' '_')"
    done
elif [ "$target" = scenario ]; then
    find ../testsuite/scenarios -name '*.scn' -size -4k | head -400 | while read -r f; do
        cp "$f" "$seeds/$(echo "$f" | tr '/' '_')"
    done
else
    for f in ../examples/*.il ../testsuite/programs/*.il; do cp "$f" "$seeds/"; done
    # Inline programs of scenarios are good programs too.
    find ../testsuite/scenarios -name '*.scn' -size -4k | head -300 | while read -r f; do
        awk '/^program <</{p=1;next} /^>>$/{p=0} p' "$f" > "$seeds/$(echo "$f" | tr '/' '_').il"
    done
    find "$seeds" -empty -delete
fi
export AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1
cargo afl fuzz -V "$seconds" -t 2000 -i "$seeds" -o "target/afl/$target" "../target/release/afl_$target"
