"""The meschers application: the command line, the comparison study and its report.

It uses the three libraries (:mod:`meschers_igl`, :mod:`pyvista_views`, :mod:`meshlab_filters`);
none of them imports it.
"""

from meschers_igl import __version__

__all__ = ["__version__"]
