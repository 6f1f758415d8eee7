"""`python -m wearjoint` runs the command line."""
from .cli import console

console()
