"""File input and output: model files (TOML), tables (CSV), figures; all writes atomic."""

from .atomic import atomic_write, check_not_input
from .model_file import load_model, save_model

__all__ = ["load_model", "save_model", "atomic_write", "check_not_input"]
