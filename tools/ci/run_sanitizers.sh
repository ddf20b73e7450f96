#!/usr/bin/env bash
# The sanitizer build: every target compiled with AddressSanitizer and
# UndefinedBehaviorSanitizer, any finding fatal (only LCM users excused from
# UBSan's vptr check, see CMakeLists.txt), then its tests.
#   no argument: the CI subset below, in the instrumented clang build that the
#     fuzz targets share (tools/ci/configure_instrumented.sh, build-fuzz/), only
#     the targets it needs;
#   a ctest regex (e.g. '.', the whole suite): every target, the Python package
#     too, with GCC in build-sanitize/; its pytest suites run with GCC's ASan
#     runtime preloaded into the interpreter (tests/python/CMakeLists.txt).
# Usage: tools/ci/run_sanitizers.sh [ctest regex]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
# A regex starts the whole instrumented build: an option-looking argument is
# a mistake (--help included), refused before anything is built.
case "${1:-}" in
  -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  -*) echo "run_sanitizers.sh: unknown option '$1' (usage: tools/ci/run_sanitizers.sh [ctest regex])" >&2; exit 2 ;;
esac
[ $# -le 1 ] || { echo "run_sanitizers.sh: one ctest regex at most, got $#" >&2; exit 2; }
# The CI subset: what meets hostile input (issue 13: the loaders, the outputs,
# the network receive path, the log reader and writer, the command gate, the
# fault schedule reader, the controller's configuration), the firmware core
# and the dynamics core (the step without allocation, checkpoints, the
# simulator) and the command line; only the targets they need. The rest of the
# suite builds and runs the same way with a regex argument (e.g. '.').
targets=(gimbalsim hostile_input_test output_policy_test scene_test key_registry_test simulator_test
         checkpoint_test no_alloc_test udpm_reassembler_test lcm_log_test lcm_url_test command_gate_test
         fault_schedule_test firmware_core_test controller_config_test)
suites='HostileInput|Paths|OutputPolicy|Scene|KeyRegistry|Simulator|Checkpoint|NoAlloc'
suites+='|UdpmReassembler|LcmLog|LcmUrl|CommandAcceptance|CommandGate|FaultInjection|FaultScheduleFile'
suites+='|Firmware|FirmwareConfig|GaussianNoise|Histogram|SpscRing|ControllerConfig'
regex=${1:-"^($suites)\\.|^cli_"}
if [[ $# -gt 0 ]]; then
  # -O1: the sanitizers' usual level, and far cheaper to compile than -O3 under ASan.
  build=${GIMBALSIM_SANITIZE_BUILD:-build-sanitize}
  targets=(all)
  cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=g++ -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -g1" \
    -DGIMBALSIM_CHECKED=ON -DGIMBALSIM_SANITIZE=address,undefined -DGIMBALSIM_PYTHON=ON >/dev/null
else
  build=${GIMBALSIM_SANITIZE_BUILD:-build-fuzz}
  bash tools/ci/configure_instrumented.sh "$build"
fi
start=$(date +%s)
cmake --build "$build" -j2 --target "${targets[@]}"
built=$(date +%s)
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$build" --output-on-failure -j2 -R "$regex"
echo "run_sanitizers.sh: build $((built - start)) s, tests $(($(date +%s) - built)) s"
