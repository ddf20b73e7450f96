#!/usr/bin/env bash
# Installs the Debian packages gimbalsim needs. Idempotent: quiet and fast when
# everything is already present. Run as root (or with sudo available).
set -euo pipefail

PKGS=(
  build-essential cmake pkg-config
  libeigen3-dev libboost-dev
  liblcm-dev liblcm-bin libglib2.0-dev
  libcli11-dev libyaml-cpp-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-matplotlib python3-numpy python3-scipy python3-yaml
  pybind11-dev python3-pybind11 python3-dev python3-pytest python3-pyflakes
  python3-dask python3-distributed python3-optuna python3-psutil python3-tqdm
  python3-setuptools python3-wheel python3-build python3-venv python3-pip
  rt-tests clang-14 libclang-rt-14-dev
  iproute2 util-linux
)

missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "bootstrap: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "bootstrap: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq >/dev/null
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "bootstrap: done" >&2
