"""UI flow tests: config, options, reauth, reconfigure and subentry flows, as a user fills them."""
