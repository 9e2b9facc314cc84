"""Model tests: the stored configuration as typed data and its checks, at every door."""
