"""Descent steps and window certificates checked by the validator (found by mutation testing)."""
