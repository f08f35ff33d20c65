#!/usr/bin/env bash
# Installs the Debian 12 packages ecpair needs to build, test and run.
# Safe to run again: packages already installed are left alone.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libboost-dev libboost-program-options-dev
  libpcap-dev libtinyxml2-dev libspdlog-dev libfmt-dev libsystemd-dev
  catch2 libprotobuf-dev protobuf-compiler
  libbenchmark-dev
  libbpf-dev bpftool clang libclang-rt-dev llvm
  iproute2 tshark procps iputils-ping
)

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps.sh: run as root (apt-get needs it)" >&2
  exit 1
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps.sh: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
