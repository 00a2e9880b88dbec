"""Ink tables: the schema shared with the plugin, angular integrals, and the tier builders."""

from .schema import SCHEMA_VERSION, InkTable, TableError, read_table, validate, write_table

__all__ = ["SCHEMA_VERSION", "InkTable", "TableError", "read_table", "validate", "write_table"]
