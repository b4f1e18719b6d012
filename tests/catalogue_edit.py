"""A catalogue planet file with one value changed, written for a test (the planet-file tests' shared edit)."""

from __future__ import annotations

import re

from wobble.io.catalog import catalogue_file


def catalogue_with(tmp_path, body: str, key: str, value: str, name: str = "edited.toml"):
    """``data/bodies/BODY.toml`` with ``parameters.KEY.value`` set to ``value`` (as TOML text), at tmp_path/name."""
    text = catalogue_file(body).read_text()
    edited = re.sub(rf"(\[parameters\.{key}\]\nvalue = )[^\n]*", rf"\g<1>{value}", text)
    assert edited != text, f"no parameters.{key} to edit in {body}"
    path = tmp_path / name
    path.write_text(edited)
    return path
