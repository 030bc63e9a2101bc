"""No '#' in any exported name: CSV readers that strip comments cut a line at '#'.

Every name an exporter writes (image names, GCP ids) reaches it inside the value types
of designer.core.truth, whose constructors refuse '#'; the exports' own '#' are
comment lines (COLMAP .txt headers, designer and Metashape CSV headers) only.
"""

import json

import numpy as np
import pytest

from designer.core.truth import CameraPose, GcpObservation, GroundControlPoint
from designer.errors import InvalidDataError
from designer.export import write_all
from tests.synthetic import ORIGIN_WORLD


@pytest.mark.parametrize("make", [
    lambda name: CameraPose(name, ORIGIN_WORLD, np.eye(3)),
    lambda name: GroundControlPoint(name, "control", ORIGIN_WORLD, ORIGIN_WORLD, [0.01] * 3),
    lambda name: GcpObservation(name, "a.png", [1.0, 2.0]),
    lambda name: GcpObservation("GCP01", name, [1.0, 2.0]),
])
@pytest.mark.parametrize("name", ["IMG#1.png", "#GCP", "GCP#"])
def test_names_with_a_hash_are_refused_where_exported_names_are_made(make, name):
    with pytest.raises(InvalidDataError, match="'#'"):
        make(name)


def test_every_hash_in_every_exported_file_starts_a_comment_line(tmp_path, make_survey):
    interior, poses, gcps, obs = make_survey(60)
    paths = write_all(tmp_path, interior, poses, gcps, obs, "EPSG:32632")
    # every text file (the COLMAP database is SQLite: its names are checked on their way in)
    files = [p for p in tmp_path.rglob("*") if p.is_file() and p.suffix != ".db"]
    assert {p.suffix for p in files} == {".txt", ".csv", ".xml", ".json"}
    for path in files:
        text = path.read_text(encoding="utf-8")
        if path.suffix in (".xml", ".json"):
            assert "#" not in text, path
            continue
        for line in text.splitlines():
            assert "#" not in line or line.startswith("#"), (path, line)
    # the names themselves are all there (nothing was cut)
    names = {p.image_name for p in poses} | {g.gcp_id for g in gcps}
    written = " ".join(p.read_text() for p in files if p.suffix != ".json")
    assert all(n in written for n in names)
    assert json.loads(paths["colmap_offset"].read_text())["choice"] == "local"
