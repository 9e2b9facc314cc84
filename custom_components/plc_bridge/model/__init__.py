"""The stored configuration as typed data, and its checks (no runtime, no flows)."""
