"""wobble's data catalogue, installed as ``wobble._data`` (see data/README.md)."""
