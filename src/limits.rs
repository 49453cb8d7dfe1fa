//! Limits on how much work a script may ask for, so that no input, careless or hostile,
//! can crash, hang or exhaust the machine.
//!
//! Every limit has a name, a default that the examples stay far below, and a
//! command-line switch to raise it (`--limit list_items=50000000`). A script that reaches
//! a limit gets a diagnostic naming the limit and how to raise it ([`Limit::help`]);
//! `docs/limits.md` lists them all. This module is a leaf: every stage may read it, it
//! reads nothing.

use std::fmt;

/// One limit: what it bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Limit {
    /// Nesting of expressions, blocks and lists in the source (parser depth); each
    /// operation of a chain after the first is a level too, so the tree every later
    /// pass recurses over is never deeper than twice this.
    Nesting,
    /// Nesting of function calls during evaluation (call depth).
    CallDepth,
    /// Total evaluation steps of one build (expressions evaluated and builtin calls),
    /// so exponential recursion within the depth limit stops.
    Work,
    /// Items in one list, and items made by all lists of one evaluation together.
    ListItems,
    /// Bytes in one string.
    StringBytes,
    /// Samples and points asked of one builtin (`linspace`, sections, sketch commands,
    /// a curve's export points).
    Samples,
    /// Vertices of one tessellated or read mesh.
    MeshVertices,
    /// Bytes of one file read (a script, a module, an OBJ, an MTL).
    FileBytes,
    /// Mebibytes of heap the process may hold while a script is evaluated
    /// (counted by the `heap` module): values that are few but large (records holding closures,
    /// say) pass the item limits and still take gigabytes.
    MemoryMb,
}

impl Limit {
    /// Every limit, in the order `docs/limits.md` lists them.
    pub const ALL: [Limit; 9] = [
        Limit::Nesting,
        Limit::CallDepth,
        Limit::Work,
        Limit::ListItems,
        Limit::StringBytes,
        Limit::Samples,
        Limit::MeshVertices,
        Limit::FileBytes,
        Limit::MemoryMb,
    ];

    /// The name used on the command line and in diagnostics.
    pub fn name(self) -> &'static str {
        match self {
            Limit::Nesting => "nesting",
            Limit::CallDepth => "call_depth",
            Limit::Work => "work",
            Limit::ListItems => "list_items",
            Limit::StringBytes => "string_bytes",
            Limit::Samples => "samples",
            Limit::MeshVertices => "mesh_vertices",
            Limit::FileBytes => "file_bytes",
            Limit::MemoryMb => "memory_mb",
        }
    }

    /// What the limit bounds, in a few words for diagnostics.
    pub fn what(self) -> &'static str {
        match self {
            Limit::Nesting => "levels of nesting in the source",
            Limit::CallDepth => "levels of nested function calls",
            Limit::Work => "evaluation steps",
            Limit::ListItems => "list items",
            Limit::StringBytes => "bytes in a string",
            Limit::Samples => "samples or points",
            Limit::MeshVertices => "mesh vertices",
            Limit::FileBytes => "bytes in a file read",
            Limit::MemoryMb => "MiB of memory held during evaluation",
        }
    }

    /// The limit of this name, if there is one.
    pub fn named(name: &str) -> Option<Limit> {
        Limit::ALL.into_iter().find(|l| l.name() == name)
    }

    /// The help line of a diagnostic for a script that reached this limit, with the
    /// value in force and the switch that raises it.
    pub fn help(self, limits: &Limits) -> String {
        format!(
            "the limit is {} {}; raise it with `--limit {}=N` if this is intended (see docs/limits.md)",
            limits.get(self),
            self.what(),
            self.name()
        )
    }
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The limits in force for one engine or pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    values: [u64; Limit::ALL.len()],
}

impl Default for Limits {
    /// Defaults far above what the examples need (the complete fender uses under a
    /// hundredth of each) and far below what exhausts a 2-core, 24 GiB machine.
    fn default() -> Self {
        let mut limits = Limits {
            values: [0; Limit::ALL.len()],
        };
        for l in Limit::ALL {
            limits.values[l as usize] = match l {
                Limit::Nesting => 128,
                Limit::CallDepth => 200,
                Limit::Work => 50_000_000,
                Limit::ListItems => 10_000_000,
                Limit::StringBytes => 16 << 20,
                Limit::Samples => 1_000_000,
                Limit::MeshVertices => 20_000_000,
                Limit::FileBytes => 256 << 20,
                Limit::MemoryMb => 8192,
            };
        }
        limits
    }
}

impl Limits {
    /// The value of one limit.
    pub fn get(&self, limit: Limit) -> u64 {
        self.values[limit as usize]
    }

    /// The value of one limit as a count of items (saturating on 32-bit targets).
    pub fn count(&self, limit: Limit) -> usize {
        usize::try_from(self.get(limit)).unwrap_or(usize::MAX)
    }

    /// Sets one limit.
    pub fn set(&mut self, limit: Limit, value: u64) {
        self.values[limit as usize] = value;
    }

    /// Applies a `NAME=VALUE` setting from the command line; the error says what is
    /// wrong and lists the names.
    pub fn apply(&mut self, setting: &str) -> Result<(), String> {
        let (limit, value) = parse_setting(setting)?;
        self.set(limit, value);
        Ok(())
    }
}

/// Parses a `NAME=VALUE` limit setting (`list_items=50000000`, underscores allowed in
/// the number).
pub fn parse_setting(setting: &str) -> Result<(Limit, u64), String> {
    let names = || {
        Limit::ALL
            .iter()
            .map(|l| l.name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some((name, value)) = setting.split_once('=') else {
        return Err(format!(
            "expected NAME=VALUE, such as `work=100000000` (limits: {})",
            names()
        ));
    };
    let name = name.trim();
    let Some(limit) = Limit::named(name) else {
        return Err(format!("no limit is named `{name}` (limits: {})", names()));
    };
    let digits: String = value.trim().chars().filter(|&c| c != '_').collect();
    match digits.parse::<u64>() {
        Ok(v) if v > 0 => Ok((limit, v)),
        _ => Err(format!(
            "the value of `{name}` must be a whole number above 0, not `{}`",
            value.trim()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_parse_or_say_why_not() {
        let mut limits = Limits::default();
        limits.apply("list_items=1_000").expect("a valid setting");
        assert_eq!(limits.get(Limit::ListItems), 1000);
        assert!(limits.apply("lists=3").unwrap_err().contains("list_items"));
        assert!(limits
            .apply("work=-1")
            .unwrap_err()
            .contains("whole number"));
        assert!(limits.apply("work").unwrap_err().contains("NAME=VALUE"));
        assert!(Limit::Work.help(&limits).contains("--limit work=N"));
    }

    #[test]
    fn every_limit_has_its_own_name() {
        for l in Limit::ALL {
            assert_eq!(Limit::named(l.name()), Some(l));
        }
    }
}
