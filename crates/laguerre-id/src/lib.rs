//! ARX and ARX-Laguerre system identification (Piltan 2020, ch. 4-5)
