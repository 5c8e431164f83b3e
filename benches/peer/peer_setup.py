"""The Mitsuba harness's set-up, run by the system Python before the harness re-runs itself in its venv: the venv
with Mitsuba and numpy, Debian's libLLVM 19 unpacked beside it, Prism built (and its profile-guided binary when
`--pgo` asks for it). Also the paths and the two helpers every part of the harness uses. See mitsuba_compare.py.
"""
import hashlib
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REFS = ROOT.parent / "shared" / "refs"
PEER = ROOT / "target" / "peer"
VENV = PEER / "venv"
LLVM_DIR = PEER / "llvm19"
MITSUBA_VERSION = "3.9.1"
PLAIN_BINARY = ROOT / "target" / "release" / "prism"


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"error: {' '.join(map(str, cmd))} failed ({r.returncode}):\n{r.stderr.strip()[-2000:]}")
    return r


# ---------------------------------------------------------------- set-up (system Python)

def libllvm_path():
    hits = sorted(LLVM_DIR.glob("usr/lib/*/libLLVM.so.19*")) + sorted(LLVM_DIR.glob("usr/lib/*/libLLVM-19.so*"))
    return hits[0] if hits else None


PGO_BINARY = ROOT / "target" / "pgo" / "prism"


PGO_SOURCES_HASH = PGO_BINARY.with_name("prism.sources-sha256")


def pgo_sources():
    """The files the binary is built from, in a fixed order."""
    return sorted([ROOT / "Cargo.toml", ROOT / "Cargo.lock", *(ROOT / "src").rglob("*.rs"),
                   *(ROOT / "plugins").rglob("*.rs")])


def pgo_sources_hash():
    """SHA-256 over the sources' paths and contents: equal when the code is, whatever the files' times."""
    h = hashlib.sha256()
    for f in pgo_sources():
        if f.exists():
            h.update(str(f.relative_to(ROOT)).encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def pgo_up_to_date():
    """True when target/pgo/prism exists and was built from today's sources: the hash the script recorded after
    its last build matches (a `git checkout` that rewrites files without changing them does not force a rebuild);
    without a recorded hash (a build run by hand), when it is newer than every source file."""
    if not PGO_BINARY.exists():
        return False
    if PGO_SOURCES_HASH.exists():
        return PGO_SOURCES_HASH.read_text().strip() == pgo_sources_hash()
    built = PGO_BINARY.stat().st_mtime
    return all(f.stat().st_mtime <= built for f in pgo_sources() if f.exists())


def build_pgo():
    """Run benches/pgo/build.sh and record the hash of the sources it built from (taken before it starts)."""
    digest = pgo_sources_hash()
    PGO_SOURCES_HASH.unlink(missing_ok=True)
    log("benches/pgo/build.sh (the profile-guided binary, about 5 minutes) ...")
    run([str(ROOT / "benches" / "pgo" / "build.sh")], cwd=ROOT)
    PGO_SOURCES_HASH.write_text(digest + "\n")


def bootstrap(script):
    """Create the venv and unpack libLLVM 19 if needed, build Prism, then re-run `script` (the harness) in the venv."""
    PEER.mkdir(parents=True, exist_ok=True)
    py = VENV / "bin" / "python"
    if not py.exists():
        log(f"creating {VENV.relative_to(ROOT)} ...")
        run([sys.executable, "-m", "venv", str(VENV)])
    if run([str(py), "-m", "pip", "list", "--format=freeze"]).stdout.find(f"mitsuba=={MITSUBA_VERSION}") < 0:
        log(f"pip install mitsuba=={MITSUBA_VERSION} numpy ...")
        run([str(py), "-m", "pip", "install", "--quiet", f"mitsuba=={MITSUBA_VERSION}", "numpy"])
    if libllvm_path() is None:
        deb_dir = PEER / "deb"
        deb_dir.mkdir(exist_ok=True)
        log("apt-get download libllvm19 ...")
        if subprocess.run(["apt-get", "download", "libllvm19"], cwd=deb_dir, capture_output=True).returncode != 0:
            run(["apt-get", "update"])
            run(["apt-get", "download", "libllvm19"], cwd=deb_dir)
        debs = sorted(deb_dir.glob("libllvm19_*.deb"))
        if not debs:
            sys.exit("error: apt-get download libllvm19 produced no .deb")
        run(["dpkg", "-x", str(debs[-1]), str(LLVM_DIR)])
        if libllvm_path() is None:
            sys.exit(f"error: no libLLVM.so.19 under {LLVM_DIR}")
    log("cargo build --release ...")
    run(["cargo", "build", "--release", "--quiet"], cwd=ROOT)
    if "--pgo" in sys.argv[1:] and not pgo_up_to_date():
        build_pgo()
    env = dict(os.environ, DRJIT_LIBLLVM_PATH=str(libllvm_path()), PRISM_PEER_IN_VENV="1")
    os.execve(str(py), [str(py), str(script), *sys.argv[1:]], env)
