"""Generate the scikit-learn reference values hard-coded in tests/sklearn_reference.rs.

Run once:  python3 crates/classify/tests/sklearn/reference.py > /tmp/ref.txt
The dataset is drawn with numpy's legacy RandomState(2020) and rounded to 3 decimals, then
printed, so the Rust test carries the exact same numbers.
"""
import numpy as np
import sklearn
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC
from sklearn.tree import DecisionTreeClassifier

rs = np.random.RandomState(2020)
centres = np.array([[0.0, 0.0], [2.0, 0.5], [0.5, 2.0], [2.5, 2.5]])
def draw(n):
    X = np.vstack([c + 0.8 * rs.randn(n, 2) for c in centres])
    y = np.repeat(np.arange(4), n)
    return np.round(X, 3), y

Xtr, ytr = draw(25)
Xte, yte = draw(15)

sc = StandardScaler().fit(Xtr)
svm = SVC(kernel="linear", C=1.0, decision_function_shape="ovo", tol=1e-3).fit(sc.transform(Xtr), ytr)
p_svm = svm.predict(sc.transform(Xte))
dec = svm.decision_function(sc.transform(Xte))

tree = DecisionTreeClassifier(criterion="gini", random_state=0).fit(Xtr, ytr)
p_tree = tree.predict(Xte)
t = tree.tree_
thr = sorted(set((int(t.feature[i]), round(float(t.threshold[i]), 6)) for i in range(t.node_count) if t.children_left[i] != -1))

tree2 = DecisionTreeClassifier(criterion="gini", max_depth=2, random_state=0).fit(Xtr, ytr)
p_tree2 = tree2.predict(Xte)
t2 = tree2.tree_
thr2 = [(int(t2.feature[i]), round(float(t2.threshold[i]), 6)) for i in range(t2.node_count) if t2.children_left[i] != -1]

def arr(a):
    return ", ".join(str(v) for v in a)
def rows(X):
    return ",\n".join("    [%s, %s]" % (repr(float(a)), repr(float(b))) for a, b in X)

print("// scikit-learn", sklearn.__version__, "numpy", np.__version__)
print("const X_TRAIN: [[f64; 2]; %d] = [\n%s,\n];" % (len(Xtr), rows(Xtr)))
print("const Y_TRAIN: [usize; %d] = [%s];" % (len(ytr), arr(ytr)))
print("const X_TEST: [[f64; 2]; %d] = [\n%s,\n];" % (len(Xte), rows(Xte)))
print("const Y_TEST: [usize; %d] = [%s];" % (len(yte), arr(yte)))
print("const SKLEARN_SVM_PRED: [usize; %d] = [%s];" % (len(p_svm), arr(p_svm)))
print("// min |ovo decision value| per test row (near-ties explain any difference)")
print("const SKLEARN_SVM_MIN_ABS_DECISION: [f64; %d] = [%s];" % (len(dec), ", ".join("%.4f" % v for v in np.abs(dec).min(axis=1))))
print("const SKLEARN_TREE_PRED: [usize; %d] = [%s];" % (len(p_tree), arr(p_tree)))
print("const SKLEARN_TREE_THRESHOLDS: [(usize, f64); %d] = [%s];" % (len(thr), ", ".join("(%d, %r)" % x for x in thr)))
print("const SKLEARN_TREE_LEAVES: usize = %d;" % tree.get_n_leaves())
print("const SKLEARN_TREE2_PRED: [usize; %d] = [%s];" % (len(p_tree2), arr(p_tree2)))
print("// depth-2 thresholds in node order (root, left, right)")
print("const SKLEARN_TREE2_THRESHOLDS: [(usize, f64); %d] = [%s];" % (len(thr2), ", ".join("(%d, %r)" % x for x in thr2)))
print("// svm test accuracy %.4f, tree %.4f, tree depth2 %.4f" % ((p_svm == yte).mean(), (p_tree == yte).mean(), (p_tree2 == yte).mean()))
