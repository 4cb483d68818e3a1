"""Ball-in-socket contact: compiled normal and friction laws, the clearance-joint force."""
