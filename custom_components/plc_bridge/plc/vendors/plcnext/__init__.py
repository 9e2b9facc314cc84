"""Phoenix Contact PLCnext Control through its REST data interface (`/_pxc_api`)."""

from .client import PlcnextClient
from .probe import answers

CLIENT = PlcnextClient
PROBE = answers

__all__ = ["CLIENT", "PROBE", "PlcnextClient", "answers"]
