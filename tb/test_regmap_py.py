"""Plain pytest (no simulator): the register map rdl/twh_regs.rdl, its Python
view tb/regmap.py, and the files generated from it (sw/include/twh_regs.h,
docs/registers.md: committed, must be current and the header must compile)."""
import doctest
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import regmap

REPO = regmap.REPO
GENERATED = ["sw/include/twh_regs.h", "docs/registers.md"]
HEADER = REPO / "sw/include/twh_regs.h"
CFLAGS = ["-std=gnu99", "-Wall", "-Wextra", "-Werror", "-pedantic",
          "-fsyntax-only"]
ARM_FLAGS = ["-mthumb", "-mcpu=cortex-m0"]

RM = regmap.load()


def _peakrdl_env():
    env = dict(os.environ)
    exe = Path(sys.executable).parent / "peakrdl"
    if "PEAKRDL" not in env and exe.exists():
        env["PEAKRDL"] = str(exe)
    return env


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """The generated files, made afresh the way `make regs` makes them."""
    out = tmp_path_factory.mktemp("gen")
    subprocess.run(["bash", str(REPO / "scripts/gen_regs.sh"), str(out)],
                   check=True, env=_peakrdl_env())
    return out


def _compile(cc, source, tmp_path, extra=()):
    c = tmp_path / "check.c"
    c.write_text(source)
    r = subprocess.run([cc, *CFLAGS, *extra, f"-I{HEADER.parent}", str(c)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


# ------------------------------------------------------------ the RDL itself
def test_docstring_example():
    res = doctest.testmod(regmap)
    assert res.attempted > 0 and res.failed == 0


def test_rdl_loads():
    assert RM["ID"].address == 0
    assert len(RM.all) == len({r.name for r in RM.all})
    assert RM.size > max(r.address for r in RM.all)
    assert RM.max_channels >= 1 and RM.channel_regs >= 1


def test_addresses_unique_and_aligned():
    addrs = [r.address for r in RM.all]
    assert len(addrs) == len(set(addrs))
    for r in RM.all:
        assert r.width == 32, r.name
        assert r.address % (r.width // 8) == 0, r.name
        assert r.address + r.width // 8 <= RM.size, r.name


def test_every_field_has_reset_and_access():
    for r in RM.all:
        assert r.fields, r.name
        used = 0
        for f in r.fields:
            where = f"{r.name}.{f.name}"
            assert 0 <= f.lsb <= f.msb < r.width, where
            assert not used & f.mask, f"{where} overlaps"
            used |= f.mask
            assert f.reset is not None, f"{where}: no reset"
            assert 0 <= f.reset < (1 << f.width), f"{where}: reset too wide"
            assert f.sw in ("r", "w", "rw"), where
            # the access types regmap models (read_after_write)
            assert f.onwrite in (None, "woclr"), where
            assert f.onread is None, where
            assert not (f.onwrite and f.sw != "rw"), where
            if f.singlepulse:
                assert f.sw == "w" and f.width == 1, where


def test_masks_partition_the_register():
    for r in RM.all:
        parts = [r.rw_mask, r.ro_mask, r.wo_mask, r.woclr_mask,
                 r.reserved_mask]
        union = 0
        for m in parts:
            assert not union & m, r.name
            union |= m
        assert union == r.full_mask, r.name
        assert r.read_mask == r.rw_mask | r.ro_mask | r.woclr_mask
        assert r.write_mask == r.rw_mask | r.wo_mask | r.woclr_mask
        assert r.singlepulse_mask & ~r.wo_mask == 0


def test_channel_blocks_repeat():
    ch0 = RM.channel(0)
    assert len(ch0) == RM.channel_regs
    for n in range(RM.max_channels):
        regs = RM.channel(n)
        assert [r.name.split(".", 1)[1] for r in regs] == \
            [r.name.split(".", 1)[1] for r in ch0]
        for r, r0 in zip(regs, ch0):
            assert r.address - r0.address == n * RM.channel_stride
            assert r.address in RM.channel_span(n)
            assert r.fields == r0.fields
            assert r.name == f"CH[{n}]." + r0.name.split(".", 1)[1]
    glob = [r for r in RM.all if r.channel is None]
    assert max(r.address for r in glob) < RM.channel_base


def test_default_params_match_rtl():
    """The RDL's reset values describe the RTL's default build."""
    params = regmap.default_params()
    for top in ("twh_core", "twh_wb", "twh_axil"):
        src = (REPO / "rtl" / f"{top}.v").read_text()
        for name, value in params.items():
            m = re.search(rf"parameter\s+integer\s+{name}\s*=\s*([\d_]+)",
                          src)
            assert m, f"{top}: no parameter {name}"
            assert int(m.group(1).replace("_", "")) == value, (top, name)


@pytest.mark.parametrize("channels,depth,clk_hz", [
    (1, 16, 48_000_000), (3, 64, 10_500_000), (8, 4, 200_000_000),
    (2, 32, 12_345_678)])
def test_build_parameters(channels, depth, clk_hz):
    rm = regmap.load(channels=channels, fifo_depth=depth, clk_hz=clk_hz)
    assert rm.params == {"CHANNELS": channels, "FIFO_DEPTH": depth,
                         "CLK_HZ": clk_hz}
    assert rm["VERSION"].field("CHANNELS").reset == channels
    assert rm["PARAMS"].field("FIFO_DEPTH").reset == depth
    assert rm["PARAMS"].field("CLK_KHZ").reset == clk_hz // 1000
    assert {r.channel for r in rm.registers} - {None} == set(range(channels))
    assert {r.channel for r in rm.absent} == \
        set(range(channels, rm.max_channels))
    assert len(rm.registers) + len(rm.absent) == len(RM.all)
    # the per-channel fields have one bit for each channel of the build;
    # nothing else moves
    full = regmap.load(channels=rm.max_channels)
    for r in rm.all:
        pc = [f for f in r.fields if f.per_channel]
        for f in pc:
            assert (f.lsb, f.msb) == (0, channels - 1), (r.name, f)
            assert f.mask | r.reserved_mask == full[r.name].field(f.name).mask | \
                full[r.name].reserved_mask
        if r.name not in ("VERSION", "PARAMS") and not pc:
            assert r == RM[r.name]
    assert {r.name for r in rm.all if any(f.per_channel for f in r.fields)} == \
        {"POLL_READY", "IDLE_CHARGE", "BUSY"}
    assert regmap.load(channels=channels)["PARAMS"].reset == RM["PARAMS"].reset


@pytest.mark.parametrize("kw", [
    {"channels": 0}, {"channels": 33}, {"fifo_depth": 0},
    {"fifo_depth": 4096}, {"clk_hz": 999}, {"clk_hz": (1 << 20) * 1000},
    {"clk_hz": 48e6 + 0.5}])
def test_build_parameters_refused(kw):
    with pytest.raises(ValueError):
        regmap.load(**kw)


def test_read_after_write():
    ctrl = RM["CTRL"]
    assert regmap.read_after_write(ctrl, ctrl.reset, 0xFFFFFFFF) == \
        ctrl.rw_mask
    status = RM["STATUS"]
    assert regmap.read_after_write(status, status.reset, 0xFFFFFFFF) == \
        status.reset
    errors = RM["ERRORS"]
    assert regmap.read_after_write(errors, 0x1F, 0x11) == 0x0E
    push = RM["CH[0].CMD_PUSH"]
    assert regmap.read_after_write(push, 0, 0x12345678) == 0


# ------------------------------------------------------- generated outputs
@pytest.mark.parametrize("path", GENERATED)
def test_generated_files_current(generated, path):
    fresh = (generated / path).read_text()
    committed = (REPO / path).read_text()
    assert committed == fresh, f"{path} is stale: run 'make regs'"


def test_header_compiles_gnu99(tmp_path):
    _compile("gcc", '#include "twh_regs.h"\n'
             "int twh_dummy(void);\nint twh_dummy(void) { return 0; }\n",
             tmp_path)


@pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None,
                    reason="arm-none-eabi-gcc not installed")
def test_header_compiles_arm(tmp_path):
    _compile("arm-none-eabi-gcc", '#include "twh_regs.h"\n'
             "int twh_dummy(void);\nint twh_dummy(void) { return 0; }\n",
             tmp_path, ARM_FLAGS)


def _header_macros():
    macros = {}
    for m in re.finditer(r"^#define (TWH_REGS__\w+)_(bm|bp|bw|reset) (\S+)$",
                         HEADER.read_text(), re.M):
        macros.setdefault(m.group(1), {})[m.group(2)] = int(m.group(3), 0)
    return macros


def test_header_field_macros_match_rdl():
    """Every field's _bm/_bp/_bw/_reset macro agrees with regmap (default
    build, with the per-channel fields at their full 32 channels); channel
    registers share one set of macros."""
    macros = _header_macros()
    seen = set()
    full = regmap.load(channels=32)
    for r in RM.all:
        reg = r.name.split(".")[-1]
        for f in r.fields:
            if f.per_channel:
                f = full[r.name].field(f.name)
            keys = [k for k in macros if k.endswith(f"__{reg}__{f.name}")]
            assert len(keys) == 1, (r.name, f.name, keys)
            m = macros[keys[0]]
            assert m == {"bm": f.mask, "bp": f.lsb, "bw": f.width,
                         "reset": f.reset}, (r.name, f.name)
            seen.add(keys[0])
    assert seen == set(macros)


def test_header_struct_offsets(tmp_path):
    """The struct view puts every register at its RDL address (this replaces
    the C11 packing static_assert that --std gnu99 leaves out)."""
    lines = ["#include <stddef.h>", '#include "twh_regs.h"',
             "#define CHECK(n, c) typedef char twh_check_##n[(c) ? 1 : -1]",
             f"CHECK(size, sizeof(twh_regs_t) == {RM.size:#x});"]
    for i, r in enumerate(RM.all):
        lines.append(f"CHECK(r{i}, offsetof(twh_regs_t, {r.name}) == "
                     f"{r.address:#x});   /* {r.name} */")
        lines.append(f"CHECK(s{i}, sizeof(((twh_regs_t *)0)->{r.name}) == "
                     f"{r.width // 8});")
    _compile("gcc", "\n".join(lines) + "\n", tmp_path)
