"""Examples built on the library: mechanisms other than the paper's (docs/four_bar.md)."""
