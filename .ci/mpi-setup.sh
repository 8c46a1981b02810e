#!/usr/bin/env bash
# Optional MPI environment for the `petsc` backend (docs/mpi.md): Debian's complex PETSc/SLEPc,
# petsc4py/slepc4py/mpi4py for Debian's own python3.11, and a venv made from that interpreter.
# Usage: .ci/mpi-setup.sh [VENV]   (default /opt/dhlb-mpi; needs root and apt-get)
# Prints the venv's python on the last line; exits 1 (with a message) if it cannot be set up.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="${1:-/opt/dhlb-mpi}"
if ! command -v apt-get >/dev/null 2>&1 || [ "$(id -u)" != 0 ]; then
  echo "mpi-setup: needs root and apt-get (Debian 12); skipping" >&2; exit 1
fi
pkgs="python3-petsc4py-complex python3-slepc4py-complex python3-mpi4py python3-scipy python3-venv openmpi-bin"
export DEBIAN_FRONTEND=noninteractive
apt-get install -y -q $pkgs >/dev/null 2>&1 || { apt-get update -q >/dev/null 2>&1 && apt-get install -y -q $pkgs >/dev/null; }
petsc_dir="$(ls -d /usr/lib/petscdir/petsc*/x86_64-linux-gnu-complex | sort -V | tail -1)"
slepc_dir="$(ls -d /usr/lib/slepcdir/slepc*/x86_64-linux-gnu-complex | sort -V | tail -1)"
[ -d "$venv" ] || /usr/bin/python3.11 -m venv --system-site-packages "$venv"
# petsc4py/slepc4py of the complex builds on the path without PETSC_DIR/SLEPC_DIR
site="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
printf '%s\n%s\n' "$petsc_dir/lib/python3/dist-packages" "$slepc_dir/lib/python3/dist-packages" \
  > "$site/dhlb-petsc-complex.pth"
# keep Debian's numpy/scipy (petsc4py is compiled against that numpy); everything else from pip
cons="$(mktemp)"
"$venv/bin/python" -c 'import numpy, scipy; print(f"numpy=={numpy.__version__}\nscipy=={scipy.__version__}")' > "$cons"
"$venv/bin/python" -m pip install -q -c "$cons" -e "$here" pytest hypothesis threadpoolctl
"$venv/bin/python" - <<'PY'
from petsc4py import PETSc
from slepc4py import SLEPc
import numpy as np
assert np.dtype(PETSc.ScalarType).kind == "c", "PETSc is not the complex build"
print("mpi-setup: PETSc", ".".join(map(str, PETSc.Sys.getVersion())), "SLEPc", ".".join(map(str, SLEPc.Sys.getVersion())),
      "complex; MUMPS:", PETSc.Sys.hasExternalPackage("mumps"))
PY
echo "$venv/bin/python"
