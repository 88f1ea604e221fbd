"""Exact or conventional factors from the paper's units (in, kip, psi, g) to SI."""


# Exact or conventional conversion factors to SI.
INCH = 0.0254  # [m]


FOOT = 12 * INCH  # [m]


CM = 0.01  # [m]


MM = 0.001  # [m]


LBF = 4.4482216152605  # [N]


KIP = 1000.0 * LBF  # [N]


KN = 1000.0  # [N]


PSI = LBF / INCH**2  # [Pa] = 6894.757...


KSI = 1000.0 * PSI  # [Pa]


KPA = 1.0e3  # [Pa]


MPA = 1.0e6  # [Pa]


STANDARD_GRAVITY = 9.80665  # [m/s^2]
