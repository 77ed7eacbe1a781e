#!/usr/bin/env bash
# Runs AFL++ on one ladderc fuzz target on the stable toolchain.
#   fuzz/run-afl.sh TARGET SECONDS      (TARGET: front_end | scenario | pipeline)
# Seeds come from the repository's programs and scenarios; findings land in
# target/afl/TARGET/default/crashes.
set -euo pipefail
cd "$(dirname "$0")"
target=${1:?target: front_end, scenario or pipeline}
seconds=${2:-600}
command -v cargo-afl >/dev/null || cargo install --locked cargo-afl
cargo afl build --release --no-default-features --features afl --bin "afl_$target"
seeds=target/afl/$target/seeds
mkdir -p "$seeds"
if [ "$target" = scenario ]; then
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
cargo afl fuzz -V "$seconds" -t 2000 -i "$seeds" -o "target/afl/$target" "target/release/afl_$target"
