"""Phoenix Contact PLCnext Control through its REST data interface (`/_pxc_api`)."""

from .client import PlcnextClient

CLIENT = PlcnextClient

__all__ = ["CLIENT", "PlcnextClient"]
