//! One-vs-one linear SVM and Gini trees on linfa, with honest evaluation protocols
