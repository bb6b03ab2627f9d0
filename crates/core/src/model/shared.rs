//! The operators a model builds from its mesh and its bodies' makeup alone (the sparsity pattern
//! and the mass matrix, the element data of the strain energy and of the stress recovery, the
//! gravity loads, the rigid-body functionals), shared by the models of one process that are
//! built from the same inputs: the cases of a sweep over the start, the time step, the material's
//! stiffness or the torque, FMU instances and Python simulations of one pendulum: each is built
//! once instead of once per case.
//!
//! Each is kept as an `Arc` under a key that hashes everything it is built from (the mesh's
//! fingerprint, its size and element order, the element range of the body, the density,
//! thickness or gravity that enter it) and its type; a model holds its own `Arc`s, so a shared
//! operator is never changed and never outlives its last user plus this store. The store keeps the
//! last [`KEPT`] operators used (two models' worth); [`forget_shared`] empties it (a benchmark of
//! a whole run builds as a fresh process does).

use std::any::{Any, TypeId};
use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::{Arc, Mutex, PoisonError};

use crate::mesh::Mesh;

/// Operators kept at most, the least recently used dropped first.
pub const KEPT: usize = 12;

/// Kept operators, the most recently used last.
#[derive(Default)]
struct Store(Vec<(TypeId, u64, Arc<dyn Any + Send + Sync>)>);

impl Store {
    fn get<T: Any + Send + Sync>(&mut self, k: u64) -> Option<Arc<T>> {
        let i = self
            .0
            .iter()
            .position(|(t, kk, _)| *t == TypeId::of::<T>() && *kk == k)?;
        let entry = self.0.remove(i);
        let value = Arc::clone(&entry.2);
        self.0.push(entry);
        value.downcast::<T>().ok()
    }

    fn put<T: Any + Send + Sync>(&mut self, k: u64, value: &Arc<T>) {
        if self.0.iter().any(|(t, kk, _)| *t == TypeId::of::<T>() && *kk == k) {
            return;
        }
        if self.0.len() >= KEPT {
            self.0.remove(0);
        }
        self.0
            .push((TypeId::of::<T>(), k, Arc::clone(value) as Arc<dyn Any + Send + Sync>));
    }
}

static STORE: Mutex<Store> = Mutex::new(Store(Vec::new()));

/// The key of an operator: a hash of what it is built from. The mesh enters through its
/// fingerprint, its node, element and edge counts and its order.
#[derive(Clone)]
pub(crate) struct Key(DefaultHasher);

impl Key {
    /// The key of an operator on `mesh`, whose fingerprint is `fingerprint`.
    pub(crate) fn on(mesh: &Mesh, fingerprint: u64) -> Self {
        let mut h = DefaultHasher::new();
        (
            fingerprint,
            mesh.nodes.len(),
            mesh.triangles.len(),
            mesh.boundary_edges.len(),
            mesh.order,
        )
            .hash(&mut h);
        Self(h)
    }

    /// This key with `values` (sizes, indices, index pairs) added.
    pub(crate) fn with<H: Hash + ?Sized>(mut self, values: &H) -> Self {
        values.hash(&mut self.0);
        self
    }

    /// This key with the numbers `values` (their IEEE bits) added.
    pub(crate) fn with_f64(mut self, values: &[f64]) -> Self {
        for v in values {
            v.to_bits().hash(&mut self.0);
        }
        self
    }

    fn value(&self) -> u64 {
        self.0.finish()
    }
}

/// The operator of type `T` under `key`: the kept one, or the one `build` makes (then kept).
pub(crate) fn shared<T: Any + Send + Sync>(key: &Key, build: impl FnOnce() -> T) -> Arc<T> {
    let built: Result<_, std::convert::Infallible> = shared_in(&STORE, key, || Ok(build()));
    built.unwrap_or_else(|e| match e {})
}

/// As [`shared`], for a build that can fail (a failure is not kept).
pub(crate) fn try_shared<T: Any + Send + Sync, E>(
    key: &Key,
    build: impl FnOnce() -> Result<T, E>,
) -> Result<Arc<T>, E> {
    shared_in(&STORE, key, build)
}

/// [`try_shared`] on `store`. The build runs without the lock (other models' operators are not
/// held up); two threads asking for the same new operator at once both build it, one is kept.
fn shared_in<T: Any + Send + Sync, E>(
    store: &Mutex<Store>,
    key: &Key,
    build: impl FnOnce() -> Result<T, E>,
) -> Result<Arc<T>, E> {
    let k = key.value();
    if let Some(v) = store.lock().unwrap_or_else(PoisonError::into_inner).get(k) {
        return Ok(v);
    }
    let value = Arc::new(build()?);
    store.lock().unwrap_or_else(PoisonError::into_inner).put(k, &value);
    Ok(value)
}

/// Empties the store: the next model builds every operator, as in a fresh process (a benchmark of a
/// whole run; see also [`crate::mesh::forget_last`]).
pub fn forget_shared() {
    STORE.lock().unwrap_or_else(PoisonError::into_inner).0.clear();
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build<T>(count: &mut usize, value: T) -> Result<T, &'static str> {
        *count += 1;
        Ok(value)
    }

    #[test]
    fn an_operator_is_built_once_per_key_and_type_and_the_least_recently_used_goes_first() {
        let store = Mutex::new(Store::default());
        let key = Key(DefaultHasher::new()).with(&[3]);
        let mut builds = 0;
        let a = shared_in(&store, &key, || build(&mut builds, vec![1.0f64])).unwrap();
        let b = shared_in(&store, &key, || build(&mut builds, vec![2.0f64])).unwrap();
        assert!(Arc::ptr_eq(&a, &b), "the second model shares the first one's operator");
        assert_eq!(builds, 1);
        // the same key for another type, and another key, are other operators
        let c = shared_in(&store, &key, || build(&mut builds, 7u32)).unwrap();
        let d = shared_in(&store, &key.clone().with_f64(&[0.5]), || {
            build(&mut builds, vec![3.0f64])
        })
        .unwrap();
        assert_eq!((*c, d.as_slice(), builds), (7, &[3.0][..], 3));
        // a failed build is reported and not kept
        let other = Key(DefaultHasher::new()).with(&[4]);
        let e: Result<Arc<Vec<f64>>, _> = shared_in(&store, &other, || Err("refused"));
        assert!(e.is_err());
        let f = shared_in(&store, &other, || build(&mut builds, vec![4.0f64])).unwrap();
        assert_eq!((f.as_slice(), builds), (&[4.0][..], 4));
        // `a` is used again, then KEPT new ones: `a` goes, as the least recently used
        shared_in(&store, &key, || build(&mut builds, vec![0.0f64])).unwrap();
        for i in 0..KEPT {
            shared_in(&store, &key.clone().with(&[i]), || build(&mut builds, i)).unwrap();
        }
        assert_eq!(builds, 4 + KEPT);
        let again = shared_in(&store, &key, || build(&mut builds, vec![5.0f64])).unwrap();
        assert_eq!((again.as_slice(), builds), (&[5.0][..], 5 + KEPT));
    }
}
