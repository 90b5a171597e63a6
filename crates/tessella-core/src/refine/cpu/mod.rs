//! The CPU evaluator, on top of the plan layer (`refine::plan`): kernels, the jobs that
//! dispatch them, sinks and streaming stores, whole-frame and piece evaluation, the
//! [`Evaluator`](evaluator::Evaluator) interface and the one-shot
//! [`Refiner`](refiner::Refiner). The plan layer never imports anything from here.

pub(crate) mod adaptive;
pub(crate) mod edge_groups;
pub(crate) mod evaluate;
pub(crate) mod evaluator;
pub(crate) mod kernels;
pub(crate) mod nontemporal;
pub(crate) mod output;
pub(crate) mod refiner;
pub(crate) mod stream;
pub(crate) mod uniform;
