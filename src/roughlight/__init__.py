"""roughlight: how explicitly modelled rough surfaces reflect light."""

__version__ = "0.1.0"
