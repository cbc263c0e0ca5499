"""The commands on SDFormat files: detection by root element, exit codes, --keep-auto."""

from __future__ import annotations

import json

from support.sdf import sdf_doc

from urdfinertia.cli import main

WORLD = sdf_doc("""<world name="w">
  <include><uri>model://ground_plane</uri></include>
  <model name="a">
    <link name="l"><inertial auto="true"/>
      <collision name="c"><geometry><box><size>0.1 0.1 0.1</size></box></geometry></collision>
    </link>
  </model>
  <model name="b">
    <link name="l"><inertial><mass>1</mass></inertial>
      <collision name="c"><geometry><mesh><uri>model://nowhere/x.stl</uri></mesh></geometry></collision>
    </link>
  </model>
</world>""")


def test_fix_world_file_isolates_links_and_reports_includes(tmp_path, capsys):
    src = tmp_path / "scene.world"
    src.write_bytes(WORLD)
    out = tmp_path / "out.world"
    code = main(["fix", "--all", str(src), "-o", str(out), "-q", "--json",
                 str(tmp_path / "r.json")])
    assert code == 1  # written, one link left as it was
    err = capsys.readouterr().err
    assert "model://ground_plane" in err and "not processed" in err
    assert "link 'b::l'" in err and "nowhere" in err
    text = out.read_text()
    assert 'auto="true"' not in text and "<mass>1</mass></inertial>" in text
    links = {r["link"]: r for r in json.loads((tmp_path / "r.json").read_text())["links"]}
    assert links["a::l"]["status"] == "recomputed"
    assert main(["check", str(out)]) in (0, 1)


def test_keep_auto_and_detection_by_root(tmp_path):
    src = tmp_path / "model.xml"  # no .sdf suffix: the root element decides
    src.write_bytes(WORLD)
    out = tmp_path / "out.sdf"
    assert main(["fix", "--all", str(src), "-o", str(out), "-q", "--keep-auto"]) == 1
    assert '<inertial auto="true"/>' in out.read_text()
