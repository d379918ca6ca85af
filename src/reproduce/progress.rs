//! What a reproduction reports as it goes. The library draws nothing: the command line turns
//! these events into progress bars and warnings.

use crate::fill::FillEvent;

/// One thing that happened.
#[derive(Clone, Copy, Debug)]
pub enum Event<'a> {
    /// A stage starts, with `total` items of what it counts ("fillings", "photographs",
    /// "shapes").
    Stage {
        stage: &'static str,
        counts: &'static str,
        total: usize,
    },
    /// Work on the stage's item called so starts.
    Working(&'a str),
    /// One more item of the stage is done.
    Done,
    /// The stage has ended.
    StageEnd,
    /// An event of the filling called so (simulate stage).
    Filling(&'a str, FillEvent),
    /// Something the user should read.
    Warning(&'a str),
}

/// Where the events go.
pub type Progress<'a> = dyn Fn(Event) + Sync + 'a;
