"""The UI flows: the config, options and subentry flows on one base with the shared steps."""
