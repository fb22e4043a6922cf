"""Model files in TOML (``docs/model-file.md``): read, validate, write."""

from __future__ import annotations

import tomllib
from pathlib import Path

from ..errors import ModelError
from ..model.machine import Model
from .atomic import atomic_write, check_not_input
from .limits import check_size

__all__ = ["load_model", "save_model"]


def load_model(path) -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or path-like
        A TOML file as ``docs/model-file.md`` describes.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        The file does not exist, is not TOML, or fails validation (the message
        names the file, table, key, value and what was expected).
    """
    path = Path(path)
    source = str(path)
    check_size(path, "model", "model file")
    try:
        text = path.read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise ModelError(source, "<file>", source, "an existing model file (no such file)") from None
    except IsADirectoryError:
        raise ModelError(source, "<file>", source, "a model file, not a folder") from None
    except UnicodeDecodeError as error:
        raise ModelError(source, "<file>", f"byte {error.start}", "UTF-8 text (TOML)") from None
    except OSError as error:
        raise ModelError(source, "<file>", source, f"a readable file ({error.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ModelError(source, "<file>", str(error), "valid TOML") from None
    return Model.from_dict(data, source=source)


def save_model(model: Model, path, inputs=()) -> None:
    """Write a model file atomically (never over one of ``inputs`` or the model's source).

    Parameters
    ----------
    model : Model
    path : str or path-like
    inputs : iterable of path-like
        Files that must not be overwritten.
    """
    import tomli_w

    check_not_input(path, [*inputs, model.source if Path(model.source).exists() else None])
    data = {k: v for k, v in model.to_dict().items() if v not in ([], None, "")}
    with atomic_write(path, "wb") as handle:
        tomli_w.dump(data, handle)
