//! 5-DOF Lagrange rolling-element bearing model, fault geometry, simulation (Piltan 2020, ch. 2-3)
