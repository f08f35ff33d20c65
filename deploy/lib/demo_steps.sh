# What both demos (deploy/demo.sh, deploy/demo-hotconnect.sh) are made of:
# headed steps, indented notes, a bounded retry, the build unless skipped.
# Source this file from the repository root (repo= set).

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }
note() { printf '   %s\n' "$*"; }

wait_for() {  # seconds command...: retries the command until it succeeds
  local seconds=$1; shift
  for _ in $(seq $((seconds * 10))); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
  "$@"
}

demo_build() {  # installs the dependencies and builds ./build, unless ECPAIR_DEMO_NO_BUILD=1
  [ "${ECPAIR_DEMO_NO_BUILD:-0}" = 1 ] && return 0
  step "Installing dependencies and building (build/, log in build.log)"
  bash deploy/build.sh >"$repo/build.log" 2>&1 || { tail -30 "$repo/build.log"; exit 1; }
}
