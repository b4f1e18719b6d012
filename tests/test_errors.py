"""InputError messages: the parameter, the value and what is allowed, on one readable line."""

from __future__ import annotations

from wobble.errors import InputError


def test_message_names_parameter_value_and_allowed():
    err = InputError("--theta0", 200.0, "an angle in [0, 180] deg")
    assert str(err) == "--theta0: got 200.0; allowed: an angle in [0, 180] deg"


def test_a_long_value_keeps_its_start_and_its_end():
    # A deep temporary folder must not hide the file's name (seen: 'got /tmp/pytest-of-root/.../nope....').
    path = "/tmp/" + "deep/" * 60 + "nope.toml"
    text = str(InputError("SCENE", path, "an existing file"))
    shown = text.split("got ", 1)[1].split(";", 1)[0]
    assert len(shown) == 200
    assert shown.startswith("/tmp/deep/") and shown.endswith("deep/nope.toml") and "..." in shown
