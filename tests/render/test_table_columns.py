"""render/table.py: which columns a terminal of a given width shows, and in what order."""

from urdfinertia.render.table import _fix_columns


def test_wide_terminals_show_every_column_notes_last():
    assert _fix_columns(None) == ["link", "mass kg", "CoM m", "principal moments kg m^2",
                                  "geometry", "notes"]
    assert _fix_columns(500)[-1] == "notes"


def test_narrow_terminals_drop_columns_but_keep_link_mass_and_notes():
    narrow = _fix_columns(60)
    assert narrow == ["link", "mass kg", "notes"]
    assert _fix_columns(1) == ["link"]
