"""The generic block library. Importing it registers every generic block (explicit imports, no scanning)."""

from blocks.library import hydraulic, mechanical, signal  # noqa: F401
