//! Gaussian memberships, rule-table and Takagi-Sugeno fuzzy inference (Piltan 2020, ch. 5)
