"""Beltrami: discrete differential geometry for VTK and ParaView.

Filters and readers follow Mark Meyer's thesis *Discrete Differential
Operators for Computer Graphics*:

>>> from beltrami import vtkDiscreteCurvatures, vtkOFFReader, vtkOFFWriter
"""
from .BeltramiFilters import *  # noqa: F401,F403
from .BeltramiIO import *  # noqa: F401,F403

__version__ = "0.1.0"
