"""Runtime tests: what a loaded entry runs (polls, writes and their guard, exposes, pulses)."""
