"""The vertical pipe handler's own components. Importing this package registers them (explicit imports)."""
