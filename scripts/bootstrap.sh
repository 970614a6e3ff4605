#!/usr/bin/env bash
# Installs whatever the project needs and is missing, and nothing else:
#  - Debian packages (as root: apt-get; otherwise print the exact command and stop)
#  - the pinned Python packages of requirements.txt into .venv
# Usage: scripts/bootstrap.sh [--waves]   (--waves also wants gtkwave)
set -euo pipefail
cd "$(dirname "$0")/.."

# command -> Debian package
tools=(iverilog:iverilog vvp:iverilog verilator:verilator yosys:yosys make:make gcc:gcc
       g++:g++ arm-none-eabi-gcc:gcc-arm-none-eabi arm-none-eabi-size:binutils-arm-none-eabi
       sigrok-cli:sigrok-cli clang-14:clang-14 bc:bc
       riscv64-unknown-elf-gcc:gcc-riscv64-unknown-elf)
[ "${1:-}" = "--waves" ] && tools+=(gtkwave:gtkwave)

missing=()
for pair in "${tools[@]}"; do
    command -v "${pair%%:*}" >/dev/null 2>&1 || missing+=("${pair##*:}")
done
[ -f /usr/include/cmocka.h ] || missing+=(libcmocka-dev)
# picolibc for the LiteX SoC's firmware (make soc)
[ -f /usr/lib/picolibc/riscv64-unknown-elf/picolibc.specs ] || missing+=(picolibc-riscv64-unknown-elf)
# libFuzzer for clang-14 (make fuzz, make fuzz-smoke)
compgen -G "/usr/lib/llvm-14/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" >/dev/null \
    || missing+=(libclang-rt-14-dev)
python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || missing+=(python3-venv)
command -v python3 >/dev/null 2>&1 || missing+=(python3)

if [ ${#missing[@]} -gt 0 ]; then
    # de-duplicate, keep order
    pkgs=$(printf '%s\n' "${missing[@]}" | awk '!seen[$0]++' | tr '\n' ' ')
    if [ "$(id -u)" -eq 0 ]; then
        echo "bootstrap: installing Debian packages: $pkgs"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        # shellcheck disable=SC2086
        apt-get install -y -qq $pkgs
    else
        echo "bootstrap: missing Debian packages. Run:"
        echo "    sudo apt-get install -y $pkgs"
        exit 1
    fi
fi

if [ ! -x .venv/bin/python ]; then
    echo "bootstrap: creating .venv"
    python3 -m venv .venv
fi
stamp=.venv/.requirements.stamp
if [ ! -f "$stamp" ] || ! cmp -s requirements.txt "$stamp"; then
    echo "bootstrap: installing requirements.txt into .venv"
    .venv/bin/python -m pip install -q --disable-pip-version-check -r requirements.txt
    cp requirements.txt "$stamp"
fi
# make compares the stamp with this script's own date too
touch "$stamp"
