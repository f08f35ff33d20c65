#!/usr/bin/env bash
# The fault campaign (issue 8): N random episodes of faults on a running pair,
# each followed by invariant checks (ecpair-fault-campaign explains them).
#
#   bash bench/fault_campaign.sh [N] [SEED]     (defaults: 200 1)
#
# Needs root and a build in ./build (or ECPAIR_BUILD_DIR). CI runs 20 episodes
# through ctest (failover.fault_campaign).
set -euo pipefail
cd "$(dirname "$0")/.."
episodes=${1:-200}
seed=${2:-1}
bin=${ECPAIR_BUILD_DIR:-$(pwd)/build}
exec "$bin/bench/ecpair-fault-campaign" --episodes "$episodes" --seed "$seed" \
  --eni "$(pwd)/tests/data/eni/twincat_kpierczy_5slaves.xml"
