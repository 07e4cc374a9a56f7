"""Unit conversions and the paper's sensor constants (SI at the package's edges).

The MEMS sensor converts stress to voltage with a conversion constant A [mV/bar]; the paper's
values (its Section 2) are the defaults everywhere a conversion constant is taken.
"""
PA_PER_BAR = 1e5
"""1 bar = 1e5 Pa."""
A_ZZ_MV_PER_BAR = 19.00
"""The paper's normal conversion constant A_zz [mV/bar]."""
A_XZ_MV_PER_BAR = 7.95
"""The paper's tangential conversion constant A_xz [mV/bar]."""
