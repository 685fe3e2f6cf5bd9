"""What a plan looks like: plots, animations and the HTML report.

:mod:`.plot`, :mod:`.animate` and :mod:`.report` each import matplotlib when first
used; ``tk.plot``, ``tk.animate`` and ``tk.report`` name them from the package's top.
"""
