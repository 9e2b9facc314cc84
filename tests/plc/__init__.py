"""Protocol-layer tests: no Home Assistant, real loopback sockets to the simulators."""
