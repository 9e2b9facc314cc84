"""What a loaded entry runs: polling, writes and their guard, exposes, outputs, issues."""
