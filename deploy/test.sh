#!/usr/bin/env bash
# README's test command, and CI's (.ci/run runs exactly this): install the
# dependencies, build, run every test. Run as root: the tests labelled
# `netns` create network namespaces (ctest -LE netns skips them).
#
# Stages, each timed (the summary at the end). CI must stay under 30 minutes
# on a 2-core machine without ccache, and compiling is most of it, so no test
# is compiled twice except the few TSan checks, and each stage builds what it
# checks. Each of the three build types a user may pick is built by one stage:
# Release by main, Debug by asan, RelWithDebInfo (its flags at -O1) by tsan.
#   main     ./build-main, Release (-O3, as packagers build it), warnings as
#            errors: the programs, the benchmarks and every test that needs
#            namespaces (veth cables, the real ecpaird and ecsim), and the
#            .deb package test
#   asan     ./build-asan, Debug with ASan + UBSan, built by clang, warnings
#            as errors: every test that needs no namespace - they are built
#            and run only here (netns test binaries are not built); this
#            stage is also the proof that Debug builds. Clang, because it
#            compiles this instrumented -O0 code in half GCC's time (CI's 30
#            minutes); GCC builds the three other stages.
#   tsan     ./build-tsan, TSan (-O1): only the targets of the threaded
#            components - the unit tests of the cycle and receive threads
#            (link, master, cable redundancy), store-and-forward and the
#            mirror (redundancy), the state machine workers (sequencer), the
#            TAP bridge and the link guard - and, in namespaces, ecpaird and
#            ecsim under TSan too: a single master to OP (operator service,
#            event pump, slave monitor), a pair that mirrors
#            (link guard heartbeat, topology verifier) and IP over the TAP
#            bridge (TAP I/O thread). deploy/tsan.supp says what is
#            suppressed and why. Instrumented, the daemons stall for tens
#            of ms: in this build the tests give the link guard, the comm
#            timeout and partner silence ten times as long and run the pair
#            at 4 ms (tests/support/ecpaird_process.cpp, pair_netns_tests.cpp);
#            the main stage checks the timing.
# Every stage is a unity build (CMAKE_UNITY_BUILD: the libraries' and
# programs' files compiled a few at a time, so the heavy headers - protobuf,
# Boost, Asio - are read once per batch, not once per file; the test files
# stay one per translation unit, tests/CMakeLists.txt), and main links without
# link-time optimisation: LTO made each of its 65 links re-optimise the
# libraries (about 10 minutes of CPU), and the tests check behaviour, not the
# last per cent of speed (the benchmarks' figures in docs/PERFORMANCE.md are
# from LTO builds). Figures: docs/PERFORMANCE.md "CI stages".
# ECPAIR_TEST_STAGES picks stages (default all three: "main asan tsan";
# their times: docs/PERFORMANCE.md "CI stages"). Every selected stage
# runs even when an earlier one failed; the exit status is 1 if any failed.
set -euo pipefail
cd "$(dirname "$0")/.."
# Ninja, for the reason deploy/build.sh gives; trees made before keep theirs.
export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"

stages=${ECPAIR_TEST_STAGES:-main asan tsan}
jobs=$(nproc)
summary=()
failed=0
# Each stage lists the tests it failed in $failures/<stage>: the summary at
# the end names them (a CI log is often read from its end).
failures=$(mktemp -d /tmp/ecpair-test-failures.XXXXXX)
trap 'rm -rf "$failures"' EXIT

# The failed assertions in a test log (Catch's "file:line: FAILED:" with the
# expression, its expansion and its INFO messages, up to the blank line that
# ends the block), for the stage's list.
failed_assertions() {
  awk '/:[0-9]+: FAILED:/ { left = 12 }
       left > 0 { if ($0 == "") { left = 0; next } print; --left }' "$@" 2>/dev/null | head -60 | sed 's/^/    /' || true
}

# ctest in a build tree; the names of the tests that failed and their failed
# assertions go to the stage's list.
run_ctest() {
  local dir=$1
  shift
  local status=0
  rm -f "$dir/Testing/Temporary/LastTestsFailed.log"  # ctest leaves an older run's when all pass
  ctest --test-dir "$dir" --output-on-failure -j2 "$@" || status=$?
  if [ "$status" -ne 0 ] && [ -f "$dir/Testing/Temporary/LastTestsFailed.log" ]; then
    sed 's/^[0-9]*://' "$dir/Testing/Temporary/LastTestsFailed.log" >>"$failures/$stage"
    failed_assertions "$dir/Testing/Temporary/LastTest.log" >>"$failures/$stage"
  fi
  return "$status"
}

stage_main() {
  bash deploy/install-deps.sh
  cmake -S . -B build-main -DCMAKE_BUILD_TYPE=Release -DECPAIR_WERROR=ON -DECPAIR_BUILD_UNIT_TESTS=OFF \
    -DCMAKE_UNITY_BUILD=ON -DECPAIR_LTO=OFF
  cmake --build build-main -j"$jobs"
  run_ctest build-main
}

stage_asan() {
  bash deploy/install-deps.sh
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_UNITY_BUILD=ON \
    -DECPAIR_WERROR=ON -DECPAIR_SANITIZE=address,undefined -DECPAIR_BUILD_BENCH=OFF -DECPAIR_BUILD_NETNS_TESTS=OFF
  cmake --build build-asan -j"$jobs"
  ASAN_SYMBOLIZER_PATH=$(command -v llvm-symbolizer) \
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    run_ctest build-asan -LE 'netns|package'
}

# The unit test binaries of the threaded components, and the namespace tests
# that start ecpaird, ecsim and ecpairctl of this build.
tsan_unit_tests=(link/link_tests master/master_tests master/cable_redundancy_tests redundancy/redundancy_tests
                 sequencer/sequencer_tests sequencer/sequencer_segment_tests tap_bridge/tap_bridge_tests
                 linkguard/linkguard_tests)
tsan_targets=(link_tests master_tests cable_redundancy_tests redundancy_tests sequencer_tests sequencer_segment_tests
              tap_bridge_tests linkguard_tests master_netns_tests pair_netns_tests tap_bridge_netns_tests
              ecpaird ecpair-linkguard ecsim ecpairctl)

stage_tsan() {
  bash deploy/install-deps.sh
  # -O1: TSan needs no more, and it compiles faster than -O2. Warnings are
  # not errors here: GCC 12 at -O1 with -fsanitize=thread reports
  # -Wmaybe-uninitialized on std::optional where -O0, -O2 and -O3 do not, and
  # the other stages hold the code to the warnings.
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_UNITY_BUILD=ON \
    -DECPAIR_SANITIZE=thread -DECPAIR_BUILD_BENCH=OFF
  cmake --build build-tsan -j"$jobs" --target "${tsan_targets[@]}"
  # TSan's shadow memory does not fit a layout randomized with more than
  # 28 bits (newer kernels' default): run the stage without randomization.
  local run=()
  if [ "$(sysctl -n vm.mmap_rnd_bits 2>/dev/null || echo 28)" -gt 28 ]; then run=(setarch "$(uname -m)" -R); fi
  local reports
  reports=$(mktemp -d /tmp/ecpair-tsan.XXXXXX)
  # Every process (the tests and the ecpaird/ecsim they start) writes its
  # reports to $reports/tsan-report.<pid>; any report fails the stage.
  export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 log_path=$reports/tsan-report suppressions=$(pwd)/deploy/tsan.supp"
  local status=0
  # Two unit test binaries at a time (one per core); each logs to its own file.
  echo "   unit tests: ${tsan_unit_tests[*]}"
  printf '%s\n' "${tsan_unit_tests[@]}" |
    xargs -P2 -I{} bash -c 'log="$1/$(basename "$3").log"
                            "${@:4}" "build-tsan/tests/$3" >"$log" 2>&1 ||
                              { echo "   FAILED: $3"; echo "$3" >>"$2"; tail -30 "$log"; exit 1; }' \
      _ "$reports" "$failures/tsan" {} "${run[@]}" || status=1
  echo "   netns: master, pair, TAP bridge"
  # Catch reads a comma in a test name as "or" unless escaped (and Catch 2.13
  # glues two name arguments into one name: several cases would be one
  # argument, comma-separated); --warn NoTests fails a binary whose names
  # matched nothing, so no case is skipped silently.
  tsan_case() {  # binary, case name
    local log
    log="$reports/$(basename "$1").case.log"
    "${run[@]}" "build-tsan/tests/$1" --warn NoTests "$2" 2>&1 | tee "$log" ||
      { echo "$1: $2" >>"$failures/tsan"; failed_assertions "$log" >>"$failures/tsan"; status=1; }
  }
  tsan_case netns/master_netns_tests "ecpaird brings a generated segment to OP with cable redundancy and data flows both ways"
  # The takeover case is not run here: under TSan the members' cycles stall
  # for more than the link guard's 50 ms, the guard takes the links down, and
  # the pair never holds a checked OP to take over from (the main stage runs it).
  tsan_case netns/pair_netns_tests "the INACTIVE mirrors the ACTIVE's image every cycle and master PD goes both ways"
  tsan_case tap_bridge/tap_bridge_netns_tests 'IP between the masters: ping both ways\, TCP with checksums\, the TAP sees only IP'
  unset TSAN_OPTIONS
  if compgen -G "$reports/tsan-report.*" >/dev/null; then
    cat "$reports"/tsan-report.* >&2
    echo "TSan reports: $(grep -h -m1 '^WARNING: ThreadSanitizer' "$reports"/tsan-report.* | sort | uniq -c | tr -s ' ' | paste -sd ';')" \
      >>"$failures/tsan"
    status=1
  fi
  rm -rf "$reports"
  return "$status"
}

for stage in $stages; do
  if ! declare -F "stage_$stage" >/dev/null; then
    echo "unknown stage '$stage' (main asan tsan)" >&2
    exit 2
  fi
done

# CPU seconds (user + system) of this shell's finished children: a stage's
# CPU time does not depend on what else the machine runs, its wall time does.
children_cpu() {
  local stat
  stat=$(<"/proc/$$/stat")
  stat=${stat##*) }  # the fields after the command name
  read -r -a fields <<<"$stat"
  echo $(( (fields[13] + fields[14]) / $(getconf CLK_TCK) ))
}

for stage in $stages; do
  echo "== stage $stage"
  started=$(date +%s)
  cpu_before=$(children_cpu)
  # A subshell in the background keeps `set -e` in force inside the stage
  # (it would be off in a condition) while this loop goes on to the next.
  ("stage_$stage") &
  status=0
  wait $! || status=$?
  elapsed=$(( $(date +%s) - started ))
  cpu=$(( $(children_cpu) - cpu_before ))
  if [ "$status" -eq 0 ]; then result=passed; else result="FAILED ($status)"; failed=1; fi
  summary+=("$(printf '%-8s %3d min %02d s wall, %3d min %02d s CPU  %s' "$stage" $((elapsed / 60)) $((elapsed % 60)) \
    $((cpu / 60)) $((cpu % 60)) "$result")")
done
echo "== stage timings ($(nproc) cores; CPU = user + system of everything the stage ran)"
printf '   %s\n' "${summary[@]}"
for stage in $stages; do
  if [ -s "$failures/$stage" ]; then
    echo "== failed in stage $stage:"
    sed 's/^/   /' "$failures/$stage"
  fi
done
exit "$failed"
