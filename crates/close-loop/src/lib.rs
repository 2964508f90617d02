//! Close the loop with measured data: residual -> missing effect -> augmented model, error before and after
