"""The scene for CAD (`scene.dxf` of `pim fit --out`) read by an independent DXF library,
ezdxf: the layers and entities the guide lists, feet as the drawing's unit, and each vehicle's
path ending at the answer's rest (result.json, SI and the natural frame) on the SAE plan."""

import json
import subprocess
from collections import Counter
from pathlib import Path

import ezdxf
import pytest

REPO = Path(__file__).resolve().parents[3]
PIM = REPO / "target" / "release" / "pim"
FOOT = 0.3048


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    if not PIM.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "pim-cli"], cwd=REPO, check=True)
    d = tmp_path_factory.mktemp("verge") / "out"
    run = subprocess.run([str(PIM), "fit", "examples/cases/reconstruction_verge_us.toml",
                          "--out", str(d)], cwd=REPO, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return d


def test_the_scene_opens_in_ezdxf_with_its_layers(out):
    doc = ezdxf.readfile(out / "scene.dxf")
    assert len(doc.audit().errors) == 0
    assert doc.header["$INSUNITS"] == 2  # feet
    layers = {layer.dxf.name for layer in doc.layers}
    assert {"CONTACT", "REST", "PATHS", "TYRE_PATHS", "EVIDENCE", "ZONES", "IMPACT"} <= layers
    kinds = Counter((e.dxftype(), e.dxf.layer) for e in doc.modelspace())
    assert kinds[("LWPOLYLINE", "CONTACT")] == 2
    assert kinds[("LWPOLYLINE", "REST")] == 2
    assert kinds[("LWPOLYLINE", "PATHS")] == 2
    assert kinds[("LWPOLYLINE", "ZONES")] == 1 and kinds[("TEXT", "ZONES")] == 1
    assert kinds[("POINT", "IMPACT")] == 1
    # Each rest (tyre points: one) and each mark of the scene: a point and its sigma circle.
    assert kinds[("POINT", "EVIDENCE")] == kinds[("CIRCLE", "EVIDENCE")] >= 4
    outlines = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "REST"]
    assert all(e.closed and len(e) == 4 for e in outlines)
    assert sorted(e.dxf.color for e in outlines) == [1, 5]
    zone = next(e for e in doc.modelspace() if e.dxftype() == "TEXT")
    assert zone.dxf.text == "friction 0.45"


def test_each_path_ends_at_the_answers_rest(out):
    doc = ezdxf.readfile(out / "scene.dxf")
    result = json.loads((out / "result.json").read_text())
    paths = {e.dxf.color: e for e in doc.modelspace()
             if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "PATHS"}
    for v in result["best"]["vehicles"]:
        rest = v["rest"]
        last = paths[5 if v["vehicle"] == 1 else 1].get_points("xy")[-1]
        # SAE on the plan: the page's right is y (the natural frame's -y), up is x; in feet.
        assert last[0] == pytest.approx(-rest["y"] / FOOT, abs=1e-6)
        assert last[1] == pytest.approx(rest["x"] / FOOT, abs=1e-6)
