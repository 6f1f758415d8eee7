"""Examples built on the library: mechanisms other than the paper's (docs/explanation/four_bar.md)."""
