#!/usr/bin/env bash
# The grains' VTK file read by a tool that is not facets: a tiny `facets sim` (30 squares in a
# 96 mm silo of rough walls 2 mm deep, a snapshot on the way), then meshio (installed from PyPI into a
# virtual environment of its own) reads grains.vtu and the snapshots. One polygon cell a grain,
# wall grains included; each poured grain's outline in mm inside the silo, centred on its
# deposit.csv row, its theta_rad that row's.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

command -v python3 >/dev/null || { echo "vtk-reader-test: FAILED: needs python3" >&2; exit 1; }
start_time=$(date +%s)
say() { echo "vtk-reader-test [$(($(date +%s) - start_time)) s]: $*"; }

# CI builds with its own profile (no whole-program optimisation); by hand, the release build.
profile=${FACETS_PROFILE:-release}
cargo build --profile "$profile" --quiet
facets="$root/target/$profile/facets"

work=$(mktemp -d /tmp/facets-vtk-reader-test.XXXXXX)
cleanup() {
    local status=$?
    if [ "$status" = 0 ]; then
        rm -rf "$work"
    else
        echo "vtk-reader-test: FAILED; outputs kept in $work" >&2
    fi
}
trap cleanup EXIT

# meshio in an environment of its own; without venv's pip, a folder on PYTHONPATH.
if python3 -m venv "$work/venv" >/dev/null 2>&1 && [ -x "$work/venv/bin/pip" ]; then
    python="$work/venv/bin/python"
    "$python" -m pip install --quiet --disable-pip-version-check meshio
else
    python=python3
    python3 -m pip install --quiet --disable-pip-version-check --target "$work/py" meshio
    export PYTHONPATH="$work/py"
fi
say "meshio $("$python" -c 'import meshio; print(meshio.__version__)') installed"

cat >"$work/tiny.toml" <<'SCENE'
[silo]
width_mm = 96
height_mm = 300
roughness_mm = 2

[grains]
kind = "square"
count = 30

[feed]
phi0 = 0.1

[run]
time_step_s = 4e-6
relaxation_ratio = 1e-3
max_relaxation_time_s = 2

[output]
snapshot_every_steps = 50000
SCENE
"$facets" sim "$work/tiny.toml" --seed 3 --out "$work/run" >"$work/sim.log" 2>&1 \
    || { cat "$work/sim.log" >&2; exit 1; }
say "facets sim done"

"$python" - "$work/run/seed-3" <<'PY'
import csv, glob, json, math, sys

import meshio
import numpy as np

run = sys.argv[1]
width_mm, height_mm, side_mm, roughness_mm = 96.0, 300.0, 6.9, 2.0
# A grain reaches into the walls' recesses, at most as deep as the flat walls behind them
# (the roughness), and overlaps a wall by less than its rounding radius (5 % of the side).
reach_mm = roughness_mm + 0.05 * side_mm

rows = list(csv.DictReader(open(f"{run}/deposit.csv")))
record = json.load(open(f"{run}/run.json"))
walls = record["wall_grains"]


def cells_of(mesh):
    """Each cell's points (mm) and its cell data, in file order."""
    assert all(b.type.startswith("polygon") for b in mesh.cells), [b.type for b in mesh.cells]
    polygons = [mesh.points[c] for b in mesh.cells for c in b.data]
    data = {name: np.concatenate(blocks) for name, blocks in mesh.cell_data.items()}
    return polygons, data


mesh = meshio.read(f"{run}/grains.vtu")
polygons, data = cells_of(mesh)
assert len(polygons) == walls + len(rows), (len(polygons), walls, len(rows))
assert walls > 0, "rough walls are built of fixed grains"
poured = np.flatnonzero(data["fixed"] == 0)
assert len(poured) == len(rows), (len(poured), len(rows))
assert list(data["grain"][poured]) == list(range(len(rows)))
assert set(data["grain"][data["fixed"] == 1]) <= {-1, -2, -3}
assert data["velocity_mm_s"].shape == (len(polygons), 3)
for k, row in zip(poured, rows):
    p = polygons[k]
    assert np.all(p[:, 2] == 0.0)
    x, y = p[:, 0], p[:, 1]
    assert x.min() > -reach_mm and x.max() < width_mm + reach_mm, (k, x.min(), x.max())
    assert y.min() > -reach_mm and y.max() < height_mm, (k, y.min(), y.max())
    # In mm, not m: the outline is a side across at its narrowest, the diagonal at most.
    across = max(x.max() - x.min(), y.max() - y.min())
    assert side_mm - 1e-6 < across < side_mm * math.sqrt(2.0), (k, across)
    centre = p[:, :2].mean(axis=0)
    assert np.allclose(centre, [float(row["x_mm"]), float(row["y_mm"])], atol=1e-3), (k, centre, row)
    theta = data["theta_rad"][k]
    assert abs(theta - float(row["theta_rad"])) < 1e-5 and 0.0 <= theta < math.pi / 2, (k, theta, row)

snapshots = sorted(glob.glob(f"{run}/snapshots/step-*.vtu"))
assert snapshots, "no snapshot written"
for path in snapshots:
    polygons, data = cells_of(meshio.read(path))
    assert walls <= len(polygons) <= walls + len(rows), (path, len(polygons))
print(f"{len(rows)} grains and {walls} wall grains read back, {len(snapshots)} snapshot(s)")
PY
say "PASSED: meshio reads grains.vtu and the snapshots"
