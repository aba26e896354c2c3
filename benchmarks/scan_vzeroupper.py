"""Scan the core's machine code for exits with the vector registers' upper halves dirty.

The hot loops are compiled for AVX-512, AVX2 and the baseline (``target_clones``). A clone
that writes a ymm/zmm register should clear the upper halves (``vzeroupper``) before control
leaves it: legacy-SSE code run after a dirty return (a baseline helper, a peer's SSE code, the
interpreter) pays for it on every instruction on CPUs with the SSE/AVX transition penalty
(Intel; the AMD EPYC this project measures on shows none). GCC inserts the instruction
itself, but GCC 12 left it out before a tail call in ``eliminate``'s clones (fixed on
2026-11-29 by inlining ``back_substitute``), and ``dot2_rows`` once returned dirty.

``python benchmarks/scan_vzeroupper.py`` builds ``lemke_core`` (Release, the package's flags,
symbols kept) in a temporary folder (or reads ``--archive``), disassembles it with objdump
and follows each function's control flow register by register: a write to ymm0-15 / zmm0-15
dirties the register, a VEX/EVEX write to its xmm half or ``vzeroupper`` cleans it. It prints
each ``ret`` or jump to another function reached with a dirty register, and the write that
dirtied it. A finding is a place to look (GCC may know better: read its
``-fdump-rtl-vzeroupper``), not a verdict; calls made while dirty are not listed. Not part of
the tests: it needs an x86-64 build, CMake and binutils.

At 2026-11-29 it listed ``tableau_lemke``'s avx2 clone: a broadcast mask left in ymm4 by a
vectorized max |.| loop reached a call to a baseline helper (``careful_sizes``, then
``lex_ties``: GCC put no vzeroupper before either) and the ``ret`` after it. Both helpers
have one caller and are now inlined into its clones; since then it finds nothing.
"""
import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_FUNCTION = re.compile(r"^[0-9a-f]+ <(.+)>:$")
_INSTRUCTION = re.compile(r"^\s+([0-9a-f]+):\t(.*)$")
_DEST = re.compile(r"%([xyz])mm([0-9]+)$")  # a vector register as the destination
_TARGET = re.compile(r"^\S+\s+([0-9a-f]+) <")


def functions(listing: str) -> dict:
    """objdump's listing as {function: [(address, instruction text), ...]}."""
    out, name = {}, None
    for line in listing.splitlines():
        if m := _FUNCTION.match(line):
            name = m.group(1)
            out[name] = []
        elif name is not None and (m := _INSTRUCTION.match(line)):
            out[name].append((int(m.group(1), 16), m.group(2).strip()))
    return out


_PREFIXES = ("notrack", "bnd", "rep", "repz", "repnz", "ds", "cs")


def dirty_exits(code: list) -> list:
    """The ``ret``s and jumps out of the function that some path reaches with the upper half
    of a vector register dirty (GCC's own model: a write to ymmN / zmmN, N < 16, dirties N;
    a VEX or EVEX write to xmmN zeroes N's upper bits; vzeroupper clears all), the state
    clean on entry, as the ABI has it. Code that no direct jump reaches (a jump table's
    targets) starts in the state of the indirect jumps before it."""
    at = {a: i for i, (a, _) in enumerate(code)}
    seen = [None] * len(code)  # None, or the registers known dirty at the instruction
    bad, todo, table = [], [(0, frozenset())], frozenset()
    origin = {}  # register -> the address of a write that dirtied it
    while todo:
        i, dirty = todo.pop()
        while i < len(code) and not (seen[i] is not None and dirty <= seen[i]):
            dirty = dirty | seen[i] if seen[i] is not None else dirty
            seen[i] = dirty
            address, text = code[i]
            words = text.split()
            while len(words) > 1 and words[0] in _PREFIXES:
                words = words[1:]
            op, operands = words[0], " ".join(words[1:])
            if op.startswith(("vzeroupper", "vzeroall")):
                dirty = frozenset()
            elif m := _DEST.search(operands.split(",")[-1].strip()):
                kind, reg = m.group(1), int(m.group(2))
                if reg < 16 and kind in "yz":
                    dirty = dirty | {reg}
                    origin[reg] = address
                elif reg < 16 and op.startswith("v"):
                    dirty = dirty - {reg}
            if op.startswith("ret"):
                if dirty:
                    bad.append((address, text, _where(dirty, origin)))
                break
            if op.startswith("j"):
                target = _TARGET.match(op + " " + operands)
                if target is None:  # jmp *%reg: a jump table
                    table = table | dirty
                elif int(target.group(1), 16) in at:
                    todo.append((at[int(target.group(1), 16)], dirty))
                elif dirty:  # a tail call
                    bad.append((address, text, _where(dirty, origin)))
                if op in ("jmp", "jmpq"):
                    break
            i += 1
        if not todo and None in seen:  # (what only a jump table reaches)
            todo.append((seen.index(None), table))
    return bad


def _where(dirty, origin) -> str:
    return ", ".join(f"%ymm{r} written at {origin[r]:#x}" if r in origin else f"%ymm{r}" for r in sorted(dirty))


def build(out: Path) -> Path:
    """lemke_core built as the package builds it (Release), into ``out``: the archive."""
    cmake = shutil.which("cmake") or "cmake"
    args = [cmake, "-S", str(ROOT), "-B", str(out), "-DLEMKE_PYTHON=OFF", "-DCMAKE_BUILD_TYPE=Release"]
    if shutil.which("ninja"):
        args += ["-G", "Ninja"]
    subprocess.run(args, check=True, capture_output=True, text=True)
    subprocess.run([cmake, "--build", str(out), "--target", "lemke_core", "-j", "2"], check=True,
                   capture_output=True, text=True)
    return next(out.glob("**/*lemke_core.a"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--archive", type=Path, help="a built liblemke_core.a (default: build one)")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        archive = a.archive or build(Path(tmp))
        listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", str(archive)], check=True,
                                 capture_output=True, text=True).stdout
    found = functions(listing)
    clones = sum(1 for name in found if ".avx512f" in name or ".avx2" in name)
    bad = {name: exits for name, code in found.items() if (exits := dirty_exits(code))}
    print(f"{len(found)} functions, {clones} clones; {len(bad)} with a dirty exit")
    for name, exits in bad.items():
        demangled = subprocess.run(["c++filt", name], capture_output=True, text=True).stdout.strip()
        print(f"  {demangled or name}")
        last = {address: (text, regs) for address, text, regs in exits}  # (the widest set)
        for address, (text, regs) in list(last.items())[:4]:
            print(f"    {address:#x} {text}  (dirty: {regs})")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
