# What both demos (deploy/demo.sh, deploy/demo-hotconnect.sh) are made of:
# headed steps, indented notes, a bounded retry, the build of what they run unless skipped.
# Source this file from the repository root (repo= set).

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }
note() { printf '   %s\n' "$*"; }

wait_for() {  # seconds command...: retries the command until it succeeds
  local seconds=$1; shift
  for _ in $(seq $((seconds * 10))); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
  "$@"
}

demo_build() {  # target...: installs the dependencies and builds the targets into ./build, unless ECPAIR_DEMO_NO_BUILD=1
  # Only the programs the demo runs: the tests and benchmarks are deploy/test.sh's and
  # deploy/build.sh's business. The log goes into the build tree, never into the repository.
  [ "${ECPAIR_DEMO_NO_BUILD:-0}" = 1 ] && return 0
  mkdir -p "$repo/build"
  local log=$repo/build/demo-build.log
  step "Installing dependencies and building $* (build/, log in build/demo-build.log)"
  ECPAIR_BUILD_TARGETS="$*" bash deploy/build.sh >"$log" 2>&1 || { tail -30 "$log"; exit 1; }
}
