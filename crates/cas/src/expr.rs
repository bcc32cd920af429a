//! Hash-consed expressions: [`Expr`] is a 4-byte handle to a node stored once in a
//! process-wide arena, so equal sub-expressions are shared and equality is handle equality.
//!
//! The arena is append-only: nodes are never freed or moved, so a node can be read without a
//! lock and handed out as `&'static Node`. Only interning a new node takes a lock. A process that
//! derives equations keeps the nodes it made; the arena is sized for hundreds of millions.
//!
//! Constructors perform the light, always-valid canonicalisation every CAS does automatically
//! (flatten sums and products, fold numbers, combine like terms and like bases, order the
//! operands deterministically). The full canonical form — expanded, trigonometry reduced,
//! fractions over a common denominator — is [`Expr::normal`] (see `normal.rs`).

use std::cmp::Ordering;
use std::hash::{BuildHasher, Hash};
use std::sync::{Mutex, OnceLock};

use hashbrown::HashTable;
use rustc_hash::{FxBuildHasher, FxHashMap};
use smallvec::SmallVec;

use crate::number::Number;

/// A handle to a hash-consed expression node. Copy, 4 bytes; `a == b` iff the expressions are
/// structurally identical.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Expr(u32);

impl std::fmt::Debug for Expr {
    /// The node with its children spelled out (the readable printers are in `print`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.node() {
            Node::Number(n) => write!(f, "{n}"),
            Node::Symbol(s) => {
                write!(f, "{}", s.name())?;
                for _ in 0..s.order() {
                    f.write_str("_d")?;
                }
                Ok(())
            }
            Node::Constant(c) => write!(f, "{c:?}"),
            Node::Add(c) => f.debug_tuple("Add").field(c).finish(),
            Node::Mul(c) => f.debug_tuple("Mul").field(c).finish(),
            Node::Pow([b, e]) => f.debug_tuple("Pow").field(b).field(e).finish(),
            Node::Func(g, c) => f.debug_tuple(g.name()).field(c).finish(),
        }
    }
}

/// An interned name.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Name(u32);

/// What a symbol stands for with respect to time.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
#[non_exhaustive]
pub enum SymbolKind {
    /// A quantity that does not change with time (a parameter, a constant, a plain variable).
    Constant,
    /// Time, `t`.
    Time,
    /// The `order`-th time derivative of a function of time `q(t)` (a coordinate or a
    /// time-dependent input): 0 is `q`, 1 is `q̇`, 2 is `q̈`.
    TimeFunction {
        /// How many times `q` has been differentiated with respect to time.
        order: u8,
    },
}

/// A symbol: a name and its relation to time.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Symbol {
    name: Name,
    kind: SymbolKind,
}

/// The named functions of the core.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
#[non_exhaustive]
pub enum Func {
    /// Sine.
    Sin,
    /// Cosine.
    Cos,
    /// Tangent.
    Tan,
    /// Arcsine.
    Asin,
    /// Arccosine.
    Acos,
    /// Arctangent.
    Atan,
    /// Two-argument arctangent `atan2(y, x)`.
    Atan2,
    /// Exponential.
    Exp,
    /// Natural logarithm (`log` reads as `ln`, as SymPy writes it).
    Ln,
    /// Absolute value.
    Abs,
    /// Sign: -1, 0 or 1.
    Sign,
}

/// Mathematical constants.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
#[non_exhaustive]
pub enum Constant {
    /// π.
    Pi,
}

/// A node of the expression graph.
///
/// Invariants kept by the constructors: `Add` and `Mul` have at least two operands, none of the
/// same kind (they are flattened), at most one number (the first operand), operands sorted by
/// [`Expr::cmp_structure`]; a `Mul`'s number is never 1 and no two of its factors share a base.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Node {
    /// A number.
    Number(Number),
    /// A symbol.
    Symbol(Symbol),
    /// A mathematical constant.
    Constant(Constant),
    /// A sum.
    Add(Box<[Expr]>),
    /// A product.
    Mul(Box<[Expr]>),
    /// A power `[base, exponent]`; `sqrt(x)` is `x ^ (1/2)`.
    Pow([Expr; 2]),
    /// A function application.
    Func(Func, Box<[Expr]>),
}

// ---------------------------------------------------------------------------------------------
// The arena.

const CHUNK_BITS: u32 = 12;
const CHUNK_SIZE: usize = 1 << CHUNK_BITS;
const CHUNK_COUNT: usize = 1 << 16;

struct Chunk {
    slots: Box<[OnceLock<Node>]>,
}

/// The hash table of the arena. Each entry keeps its node's hash, so growing the table does
/// not hash every node again and a probe rejects most non-matching nodes without reading them.
struct Interner {
    table: HashTable<(u64, u32)>,
    len: u32,
}

/// The chunk directory is a static rather than a table built on first use: building 65 536
/// empty slots touched 1.5 MB (≈ 400 page faults, about 1 ms of every process that derives
/// anything), while a static's pages are only mapped when a slot on them is first used.
static CHUNKS: [OnceLock<Chunk>; CHUNK_COUNT] = [const { OnceLock::new() }; CHUNK_COUNT];

fn chunks() -> &'static [OnceLock<Chunk>] {
    &CHUNKS
}

fn interner() -> &'static Mutex<Interner> {
    static INTERNER: OnceLock<Mutex<Interner>> = OnceLock::new();
    INTERNER.get_or_init(|| {
        Mutex::new(Interner {
            table: HashTable::new(),
            len: 0,
        })
    })
}

fn node_of(id: u32) -> &'static Node {
    let chunk = chunks()[(id >> CHUNK_BITS) as usize]
        .get()
        .expect("an Expr handle always points at an initialised chunk");
    chunk.slots[(id as usize) & (CHUNK_SIZE - 1)]
        .get()
        .expect("an Expr handle always points at an initialised node")
}

/// A node with operands, named without its operands so that it can be looked up from a
/// borrowed slice.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Compound {
    Add,
    Mul,
    Pow,
    Func(Func),
}

/// The hash of a node with operands; [`node_hash`] agrees with it, so a node can be found
/// from its parts before any of it is allocated.
fn compound_hash(kind: Compound, operands: &[Expr]) -> u64 {
    FxBuildHasher.hash_one((kind, operands))
}

fn node_hash(node: &Node) -> u64 {
    match node {
        Node::Add(c) => compound_hash(Compound::Add, c),
        Node::Mul(c) => compound_hash(Compound::Mul, c),
        Node::Pow(pair) => compound_hash(Compound::Pow, pair),
        Node::Func(f, c) => compound_hash(Compound::Func(*f), c),
        leaf => FxBuildHasher.hash_one(leaf),
    }
}

fn is_compound(node: &Node, kind: Compound, operands: &[Expr]) -> bool {
    match (node, kind) {
        (Node::Add(c), Compound::Add) | (Node::Mul(c), Compound::Mul) => **c == *operands,
        (Node::Pow(pair), Compound::Pow) => pair[..] == *operands,
        (Node::Func(f, c), Compound::Func(g)) => *f == g && **c == *operands,
        _ => false,
    }
}

fn lock_interner() -> std::sync::MutexGuard<'static, Interner> {
    // A poisoned lock only means another thread panicked while holding it; the table itself
    // is only ever extended after the node is stored, so it is still consistent.
    interner().lock().unwrap_or_else(|e| e.into_inner())
}

/// Stores a node that is not in the arena yet.
fn insert_new(guard: &mut Interner, hash: u64, node: Node) -> Expr {
    let id = guard.len;
    let chunk_index = (id >> CHUNK_BITS) as usize;
    assert!(
        chunk_index < CHUNK_COUNT,
        "expression arena exhausted ({} nodes)",
        id
    );
    let chunk = chunks()[chunk_index].get_or_init(|| Chunk {
        slots: (0..CHUNK_SIZE).map(|_| OnceLock::new()).collect(),
    });
    let _ = chunk.slots[(id as usize) & (CHUNK_SIZE - 1)].set(node);
    guard.len += 1;
    guard.table.insert_unique(hash, (hash, id), |&(h, _)| h);
    Expr(id)
}

pub(crate) fn intern(node: Node) -> Expr {
    let hash = node_hash(&node);
    let mut guard = lock_interner();
    if let Some(&(_, id)) = guard
        .table
        .find(hash, |&(h, id)| h == hash && *node_of(id) == node)
    {
        return Expr(id);
    }
    insert_new(&mut guard, hash, node)
}

/// The node `kind(operands)`, allocated only when it is new. The operands must already be in
/// the canonical order and form that the node's invariants ask for.
pub(crate) fn intern_compound(kind: Compound, operands: &[Expr]) -> Expr {
    let hash = compound_hash(kind, operands);
    let mut guard = lock_interner();
    if let Some(&(_, id)) = guard.table.find(hash, |&(h, id)| {
        h == hash && is_compound(node_of(id), kind, operands)
    }) {
        return Expr(id);
    }
    let node = match kind {
        Compound::Add => Node::Add(operands.into()),
        Compound::Mul => Node::Mul(operands.into()),
        Compound::Pow => Node::Pow([operands[0], operands[1]]),
        Compound::Func(f) => Node::Func(f, operands.into()),
    };
    insert_new(&mut guard, hash, node)
}

/// The number of distinct nodes interned so far (a work counter for benchmarks and tests).
pub fn arena_len() -> usize {
    lock_interner().len as usize
}

// ---------------------------------------------------------------------------------------------
// Names and symbols.

struct Names {
    by_text: FxHashMap<&'static str, u32>,
    len: u32,
}

fn names() -> &'static Mutex<Names> {
    static NAMES: OnceLock<Mutex<Names>> = OnceLock::new();
    NAMES.get_or_init(|| {
        Mutex::new(Names {
            by_text: FxHashMap::default(),
            len: 0,
        })
    })
}

/// The texts of the names, append-only like the expression arena, so that reading a name (the
/// structural order compares names in every sort) takes no lock.
type NameChunk = Box<[OnceLock<&'static str>]>;

/// A zero-initialised static for the same reason as the node chunk directory.
static NAME_TEXTS: [OnceLock<NameChunk>; CHUNK_COUNT] = [const { OnceLock::new() }; CHUNK_COUNT];

fn name_texts() -> &'static [OnceLock<NameChunk>] {
    &NAME_TEXTS
}

fn name_slot(id: u32) -> &'static OnceLock<&'static str> {
    let chunk = name_texts()[(id >> CHUNK_BITS) as usize]
        .get_or_init(|| (0..CHUNK_SIZE).map(|_| OnceLock::new()).collect());
    &chunk[(id as usize) & (CHUNK_SIZE - 1)]
}

impl Name {
    /// Interns a name.
    pub fn new(text: &str) -> Name {
        let mut n = names().lock().unwrap_or_else(|e| e.into_inner());
        if let Some(&id) = n.by_text.get(text) {
            return Name(id);
        }
        let leaked: &'static str = Box::leak(text.to_owned().into_boxed_str());
        let id = n.len;
        assert!(
            ((id >> CHUNK_BITS) as usize) < CHUNK_COUNT,
            "name table exhausted ({id} names)"
        );
        // The text is stored before the id is handed out, so a reader always finds it.
        let _ = name_slot(id).set(leaked);
        n.len += 1;
        n.by_text.insert(leaked, id);
        Name(id)
    }

    /// The text of the name.
    pub fn as_str(self) -> &'static str {
        name_slot(self.0)
            .get()
            .copied()
            .expect("a Name always points at a stored text")
    }
}

impl Symbol {
    /// A symbol of the given kind.
    pub fn new(name: &str, kind: SymbolKind) -> Symbol {
        Symbol {
            name: Name::new(name),
            kind,
        }
    }

    /// The symbol's name (for a rate, the name of the function it is the rate of).
    pub fn name(self) -> &'static str {
        self.name.as_str()
    }

    /// The interned name.
    pub fn name_id(self) -> Name {
        self.name
    }

    /// The symbol's kind.
    pub fn kind(self) -> SymbolKind {
        self.kind
    }

    /// The derivative order of a function of time (0 for other symbols).
    pub fn order(self) -> u8 {
        match self.kind {
            SymbolKind::TimeFunction { order } => order,
            _ => 0,
        }
    }

    /// The same function of time differentiated `k` more times; `None` for a symbol that is not
    /// a function of time or when the order would overflow.
    pub fn rate(self, k: u8) -> Option<Symbol> {
        match self.kind {
            SymbolKind::TimeFunction { order } => Some(Symbol {
                name: self.name,
                kind: SymbolKind::TimeFunction {
                    order: order.checked_add(k)?,
                },
            }),
            _ => None,
        }
    }
}

/// The factors of a product grouped by base, in the order each base first appears.
///
/// A product has a handful of factors: a list searched in order is faster than a hash map
/// (which allocated a vector per base), and an index by base is built only for long products.
#[derive(Default)]
struct Bases {
    list: Vec<Base>,
    index: Option<FxHashMap<Expr, usize>>,
}

/// One base of a product, its exponents, and the factor it came as (when it came once).
struct Base {
    base: Expr,
    exponents: SmallVec<[Expr; 2]>,
    factor: Expr,
}

/// Past this many bases, [`Bases`] keeps an index.
const BASES_SCANNED: usize = 16;

impl Bases {
    fn push(&mut self, factor: Expr) {
        let (base, exp) = split_power(factor);
        let found = match &self.index {
            Some(index) => index.get(&base).copied(),
            None => self.list.iter().position(|b| b.base == base),
        };
        if let Some(k) = found {
            self.list[k].exponents.push(exp);
            return;
        }
        if let Some(index) = &mut self.index {
            index.insert(base, self.list.len());
        }
        self.list.push(Base {
            base,
            exponents: smallvec::smallvec![exp],
            factor,
        });
        if self.index.is_none() && self.list.len() > BASES_SCANNED {
            self.index = Some(
                self.list
                    .iter()
                    .enumerate()
                    .map(|(k, b)| (b.base, k))
                    .collect(),
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Leaf constructors and access.

/// The integers whose handles are kept (see [`small_integer`]).
const SMALL_MIN: i64 = -2;
const SMALL_MAX: i64 = 2;

/// The handle of a small integer. Nearly every constructor call builds `0`, `1` or `−1`
/// (`split_power` pairs each factor with the exponent one, `mul_all` starts from a coefficient),
/// and interning one means hashing it and taking the interner's lock (in a profile of a large
/// derivation and its printing, `split_power` alone spent 3 % of the instructions on it). The
/// node is interned on first use, as before, so handles are the same as without the cache.
fn small_integer(k: i64) -> Expr {
    const SLOTS: usize = (SMALL_MAX - SMALL_MIN + 1) as usize;
    static SMALL: [OnceLock<Expr>; SLOTS] = [const { OnceLock::new() }; SLOTS];
    let slot = usize::try_from(k - SMALL_MIN).expect("k is in SMALL_MIN..=SMALL_MAX");
    *SMALL[slot].get_or_init(|| intern(Node::Number(Number::int(k))))
}

impl Expr {
    /// The node behind the handle.
    pub fn node(self) -> &'static Node {
        node_of(self.0)
    }

    /// The raw index in the arena (stable for the life of the process; not an order).
    pub fn index(self) -> u32 {
        self.0
    }

    /// A number.
    pub fn number(n: Number) -> Expr {
        match n {
            Number::Small {
                num: k @ SMALL_MIN..=SMALL_MAX,
                den: 1,
            } => small_integer(k),
            _ => intern(Node::Number(n)),
        }
    }

    /// An integer.
    pub fn int(n: i64) -> Expr {
        Expr::number(Number::int(n))
    }

    /// The rational `num/den`; `None` when `den` is zero.
    pub fn rational(num: i64, den: i64) -> Option<Expr> {
        Number::rational(num, den).map(Expr::number)
    }

    /// A float (use only for a decimal the user wrote).
    pub fn float(x: f64) -> Expr {
        Expr::number(Number::Float(x))
    }

    /// Zero.
    pub fn zero() -> Expr {
        Expr::int(0)
    }

    /// One.
    pub fn one() -> Expr {
        Expr::int(1)
    }

    /// A symbol that is constant in time (a parameter or a plain variable).
    pub fn symbol(name: &str) -> Expr {
        Expr::from_symbol(Symbol::new(name, SymbolKind::Constant))
    }

    /// A function of time `q(t)` (a generalized coordinate or a time-dependent input).
    pub fn coordinate(name: &str) -> Expr {
        Expr::from_symbol(Symbol::new(name, SymbolKind::TimeFunction { order: 0 }))
    }

    /// The `order`-th time derivative of the function of time `name`.
    pub fn rate(name: &str, order: u8) -> Expr {
        Expr::from_symbol(Symbol::new(name, SymbolKind::TimeFunction { order }))
    }

    /// Time, `t`.
    pub fn time() -> Expr {
        Expr::from_symbol(Symbol::new("t", SymbolKind::Time))
    }

    /// π.
    pub fn pi() -> Expr {
        intern(Node::Constant(Constant::Pi))
    }

    /// An expression made of one symbol.
    pub fn from_symbol(s: Symbol) -> Expr {
        intern(Node::Symbol(s))
    }

    /// The number, if this is one.
    pub fn as_number(self) -> Option<&'static Number> {
        match self.node() {
            Node::Number(n) => Some(n),
            _ => None,
        }
    }

    /// The symbol, if this is one.
    pub fn as_symbol(self) -> Option<Symbol> {
        match self.node() {
            Node::Symbol(s) => Some(*s),
            _ => None,
        }
    }

    /// Whether this is the exact number zero (structurally; see [`Expr::is_zero`] for the
    /// mathematical test).
    pub fn is_literal_zero(self) -> bool {
        matches!(self.node(), Node::Number(n) if n.is_zero())
    }

    /// Whether this is the exact number one.
    pub fn is_literal_one(self) -> bool {
        matches!(self.node(), Node::Number(n) if n.is_one())
    }

    /// The operands of a sum or product, the base and exponent of a power, the arguments of a
    /// function; empty for leaves.
    pub fn children(self) -> &'static [Expr] {
        match self.node() {
            Node::Add(c) | Node::Mul(c) | Node::Func(_, c) => c,
            Node::Pow(pair) => pair,
            _ => &[],
        }
    }

    /// A deterministic total order on expressions that does not depend on the order in which
    /// they were created, so that printed output is reproducible. Numbers come first, then
    /// symbols (by name and derivative order), constants, powers, products, sums, functions.
    pub fn cmp_structure(self, other: Expr) -> Ordering {
        if self == other {
            return Ordering::Equal;
        }
        let (a, b) = (self.node(), other.node());
        let rank = |n: &Node| match n {
            Node::Number(_) => 0,
            Node::Symbol(_) => 1,
            Node::Constant(_) => 2,
            Node::Pow(..) => 3,
            Node::Mul(_) => 4,
            Node::Add(_) => 5,
            Node::Func(..) => 6,
        };
        match rank(a).cmp(&rank(b)) {
            Ordering::Equal => {}
            o => return o,
        }
        match (a, b) {
            (Node::Number(x), Node::Number(y)) => x.total_cmp(y),
            (Node::Symbol(x), Node::Symbol(y)) => x.name().cmp(y.name()).then(x.kind.cmp(&y.kind)),
            (Node::Constant(x), Node::Constant(y)) => x.cmp(y),
            (Node::Pow([b1, e1]), Node::Pow([b2, e2])) => {
                b1.cmp_structure(*b2).then_with(|| e1.cmp_structure(*e2))
            }
            (Node::Add(x), Node::Add(y)) | (Node::Mul(x), Node::Mul(y)) => cmp_slices(x, y),
            (Node::Func(f, x), Node::Func(g, y)) => f.cmp(g).then_with(|| cmp_slices(x, y)),
            _ => Ordering::Equal,
        }
    }
}

fn cmp_slices(x: &[Expr], y: &[Expr]) -> Ordering {
    // Compare from the last (most significant) operand, so `x + y` sorts by its leading term.
    for (a, b) in x.iter().rev().zip(y.iter().rev()) {
        match a.cmp_structure(*b) {
            Ordering::Equal => continue,
            o => return o,
        }
    }
    x.len().cmp(&y.len())
}

// ---------------------------------------------------------------------------------------------
// Canonicalising constructors.

/// Splits a term into its numeric coefficient and the rest (`3*x*y` → `(3, x*y)`).
pub(crate) fn split_coefficient(term: Expr) -> (Number, Expr) {
    match term.node() {
        Node::Number(n) => (n.clone(), Expr::one()),
        Node::Mul(f) => match f[0].node() {
            Node::Number(n) => {
                let rest = if f.len() == 2 {
                    f[1]
                } else {
                    intern_compound(Compound::Mul, &f[1..])
                };
                (n.clone(), rest)
            }
            _ => (Number::ONE, term),
        },
        _ => (Number::ONE, term),
    }
}

/// Splits a factor into base and exponent (`x^2` → `(x, 2)`, `y` → `(y, 1)`).
pub(crate) fn split_power(factor: Expr) -> (Expr, Expr) {
    match factor.node() {
        Node::Pow([b, e]) => (*b, *e),
        _ => (factor, Expr::one()),
    }
}

impl Expr {
    /// The sum of the operands, canonicalised.
    pub fn add_all(terms: impl IntoIterator<Item = Expr>) -> Expr {
        let mut constant = Number::ZERO;
        let mut coefficients: FxHashMap<Expr, Number> = FxHashMap::default();
        let mut order: Vec<Expr> = Vec::new();
        let mut stack: Vec<Expr> = terms.into_iter().collect();
        stack.reverse();
        while let Some(t) = stack.pop() {
            match t.node() {
                Node::Add(inner) => stack.extend(inner.iter().rev().copied()),
                Node::Number(n) => constant = constant.add(n),
                _ => {
                    let (c, rest) = split_coefficient(t);
                    match coefficients.get_mut(&rest) {
                        Some(acc) => *acc = acc.add(&c),
                        None => {
                            coefficients.insert(rest, c);
                            order.push(rest);
                        }
                    }
                }
            }
        }
        let mut operands: Vec<Expr> = order
            .into_iter()
            .filter_map(|rest| {
                let c = &coefficients[&rest];
                if c.is_exact_zero() {
                    None
                } else {
                    Some(Expr::scale(c, rest))
                }
            })
            .collect();
        operands.sort_by(|a, b| a.cmp_structure(*b));
        if !constant.is_zero() || (constant.is_float() && operands.is_empty()) {
            operands.insert(0, Expr::number(constant));
        }
        match operands.len() {
            0 => Expr::zero(),
            1 => operands[0],
            _ => intern_compound(Compound::Add, &operands),
        }
    }

    /// `c * rest` where `rest` has no numeric factor.
    fn scale(c: &Number, rest: Expr) -> Expr {
        if c.is_exact_one() {
            return rest;
        }
        if rest.is_literal_one() {
            return Expr::number(c.clone());
        }
        let mut v: Vec<Expr> = Vec::with_capacity(4);
        v.push(Expr::number(c.clone()));
        match rest.node() {
            Node::Mul(f) => v.extend_from_slice(f),
            _ => v.push(rest),
        }
        intern_compound(Compound::Mul, &v)
    }

    /// The product of the factors, canonicalised.
    pub fn mul_all(factors: impl IntoIterator<Item = Expr>) -> Expr {
        let mut coefficient = Number::ONE;
        let mut bases = Bases::default();
        let mut stack: Vec<Expr> = factors.into_iter().collect();
        stack.reverse();
        while let Some(f) = stack.pop() {
            match f.node() {
                Node::Mul(inner) => stack.extend(inner.iter().rev().copied()),
                Node::Number(n) => coefficient = coefficient.mul(n),
                _ => bases.push(f),
            }
        }
        if coefficient.is_zero() {
            return Expr::number(coefficient);
        }
        let mut operands: Vec<Expr> = Vec::with_capacity(bases.list.len() + 1);
        let mut refold = false;
        for base in bases.list {
            let p = match base.exponents.as_slice() {
                // A power that came as one factor is that node unless it simplifies (it is
                // what `pow_raw` would intern): looking it up again costs the interner's lock.
                [exp] if base.factor != base.base => {
                    Expr::pow_simplified(base.base, *exp).unwrap_or(base.factor)
                }
                // A factor that is not a power: `pow_raw(f, 1)` is `f`.
                [_] => base.factor,
                exps => Expr::pow_raw(base.base, Expr::add_all(exps.iter().copied())),
            };
            match p.node() {
                Node::Number(n) => coefficient = coefficient.mul(n),
                // A power may split (`(2 x)^2` → `4 x^2`); fold its factors in a second pass.
                Node::Mul(_) => {
                    refold = true;
                    operands.push(p);
                }
                _ => operands.push(p),
            }
        }
        if refold {
            operands.push(Expr::number(coefficient));
            return Expr::mul_all(operands);
        }
        if coefficient.is_zero() {
            return Expr::number(coefficient);
        }
        operands.retain(|e| !e.is_literal_one());
        operands.sort_by(|a, b| a.cmp_structure(*b));
        if !coefficient.is_exact_one() || operands.is_empty() {
            operands.insert(0, Expr::number(coefficient));
        }
        match operands.len() {
            1 => operands[0],
            _ => intern_compound(Compound::Mul, &operands),
        }
    }

    /// `base ^ exp`, canonicalised.
    pub fn pow(self, exp: Expr) -> Expr {
        // What `mul_all([pow_raw(self, exp)])` gives, without a product's work in the two
        // common cases: a power node that does not simplify is its own canonical product, and
        // so is a simplification to a symbol, constant, function or sum.
        match Expr::pow_simplified(self, exp) {
            None => intern(Node::Pow([self, exp])),
            Some(p) => match p.node() {
                Node::Symbol(_) | Node::Constant(_) | Node::Func(..) | Node::Add(_) => p,
                _ => Expr::mul_all([p]),
            },
        }
    }

    fn pow_raw(base: Expr, exp: Expr) -> Expr {
        Expr::pow_simplified(base, exp).unwrap_or_else(|| intern(Node::Pow([base, exp])))
    }

    /// `base ^ exp` when it simplifies to something other than the power node itself.
    fn pow_simplified(base: Expr, exp: Expr) -> Option<Expr> {
        if exp.is_literal_zero() {
            return Some(Expr::one());
        }
        if exp.is_literal_one() {
            return Some(base);
        }
        if base.is_literal_one() {
            return Some(Expr::one());
        }
        if let (Node::Number(b), Node::Number(e)) = (base.node(), exp.node()) {
            if let Some(n) = number_power(b, e) {
                return Some(Expr::number(n));
            }
        }
        if let Node::Number(e) = exp.node() {
            if let Some(k) = e.to_i64() {
                match base.node() {
                    // (b^e)^k = b^(e k) for integer k.
                    Node::Pow([b, e2]) => {
                        return Some(Expr::pow_raw(*b, Expr::mul_all([*e2, exp])))
                    }
                    // (x y)^k = x^k y^k for integer k.
                    Node::Mul(f) => {
                        return Some(Expr::mul_all(
                            f.iter().map(|x| Expr::pow_raw(*x, Expr::int(k))),
                        ));
                    }
                    _ => {}
                }
            }
            if let (Node::Number(b), Some(_)) = (base.node(), e.to_small_ratio()) {
                if b.is_zero() && e.signum() > 0 {
                    return Some(Expr::zero());
                }
            }
        }
        None
    }

    /// `self ^ k` for an integer `k`.
    pub fn powi(self, k: i64) -> Expr {
        self.pow(Expr::int(k))
    }

    /// The square root, `self ^ (1/2)`.
    pub fn sqrt(self) -> Expr {
        self.pow(Expr::number(Number::Small { num: 1, den: 2 }))
    }

    /// Applies a named function, with the exact evaluations every reader expects
    /// (`sin 0 = 0`, `cos 0 = 1`, `exp 0 = 1`, `ln 1 = 0`).
    pub fn func(f: Func, args: Vec<Expr>) -> Expr {
        if let [a] = args.as_slice() {
            if a.is_literal_zero() {
                match f {
                    Func::Sin | Func::Tan | Func::Asin | Func::Atan | Func::Abs | Func::Sign => {
                        return Expr::zero()
                    }
                    Func::Cos | Func::Exp => return Expr::one(),
                    _ => {}
                }
            }
            if a.is_literal_one() && f == Func::Ln {
                return Expr::zero();
            }
            if let (Func::Abs, Node::Number(n)) = (f, a.node()) {
                return Expr::number(n.abs());
            }
            if let Some(e) = trig_of_inverse(f, *a) {
                return e;
            }
        }
        intern_compound(Compound::Func(f), &args)
    }

    /// Sine.
    pub fn sin(self) -> Expr {
        Expr::func(Func::Sin, vec![self])
    }
    /// Cosine.
    pub fn cos(self) -> Expr {
        Expr::func(Func::Cos, vec![self])
    }
    /// Tangent.
    pub fn tan(self) -> Expr {
        Expr::func(Func::Tan, vec![self])
    }
    /// Arcsine.
    pub fn asin(self) -> Expr {
        Expr::func(Func::Asin, vec![self])
    }
    /// Arccosine.
    pub fn acos(self) -> Expr {
        Expr::func(Func::Acos, vec![self])
    }
    /// Arctangent.
    pub fn atan(self) -> Expr {
        Expr::func(Func::Atan, vec![self])
    }
    /// `atan2(y, x)`, the angle of the point `(x, y)`.
    pub fn atan2(y: Expr, x: Expr) -> Expr {
        Expr::func(Func::Atan2, vec![y, x])
    }
    /// Exponential.
    pub fn exp(self) -> Expr {
        Expr::func(Func::Exp, vec![self])
    }
    /// Natural logarithm.
    pub fn ln(self) -> Expr {
        Expr::func(Func::Ln, vec![self])
    }
    /// Absolute value.
    pub fn abs(self) -> Expr {
        Expr::func(Func::Abs, vec![self])
    }
    /// Sign.
    pub fn sign(self) -> Expr {
        Expr::func(Func::Sign, vec![self])
    }
}

/// `b ^ e` for numbers when the result is a number (exact where possible).
fn number_power(b: &Number, e: &Number) -> Option<Number> {
    if let Some(k) = e.to_i64() {
        return b.powi(k);
    }
    if b.is_float() || e.is_float() {
        let (x, y) = (b.to_f64(), e.to_f64());
        let r = x.powf(y);
        return r.is_finite().then_some(Number::Float(r));
    }
    let (p, q) = e.to_small_ratio()?;
    let q = u32::try_from(q).ok()?;
    let root = b.exact_root(q)?;
    root.powi(p)
}

impl Func {
    /// The function's name as SymPy spells it.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Atan2 => "atan2",
            Func::Exp => "exp",
            Func::Ln => "log",
            Func::Abs => "Abs",
            Func::Sign => "sign",
        }
    }

    /// How many arguments the function takes.
    pub fn arity(self) -> usize {
        match self {
            Func::Atan2 => 2,
            _ => 1,
        }
    }

    /// Looks a function up by the names a user may write (`log` and `ln` are both `ln`).
    pub fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "asin" => Func::Asin,
            "acos" => Func::Acos,
            "atan" => Func::Atan,
            "atan2" => Func::Atan2,
            "exp" => Func::Exp,
            "ln" | "log" => Func::Ln,
            "abs" | "Abs" => Func::Abs,
            "sign" => Func::Sign,
            _ => return None,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Operators.

impl std::ops::Add for Expr {
    type Output = Expr;
    fn add(self, rhs: Expr) -> Expr {
        crate::normal::combine_normal_forms(self, rhs, false)
            .unwrap_or_else(|| Expr::add_all([self, rhs]))
    }
}

impl std::ops::Sub for Expr {
    type Output = Expr;
    fn sub(self, rhs: Expr) -> Expr {
        crate::normal::combine_normal_forms(self, rhs, true)
            .unwrap_or_else(|| Expr::add_all([self, -rhs]))
    }
}

impl std::ops::Mul for Expr {
    type Output = Expr;
    fn mul(self, rhs: Expr) -> Expr {
        Expr::mul_all([self, rhs])
    }
}

impl std::ops::Div for Expr {
    type Output = Expr;
    fn div(self, rhs: Expr) -> Expr {
        Expr::mul_all([self, rhs.powi(-1)])
    }
}

impl std::ops::Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        Expr::mul_all([Expr::int(-1), self])
    }
}

impl std::ops::Add<i64> for Expr {
    type Output = Expr;
    fn add(self, rhs: i64) -> Expr {
        self + Expr::int(rhs)
    }
}

impl std::ops::Sub<i64> for Expr {
    type Output = Expr;
    fn sub(self, rhs: i64) -> Expr {
        self - Expr::int(rhs)
    }
}

impl std::ops::Mul<i64> for Expr {
    type Output = Expr;
    fn mul(self, rhs: i64) -> Expr {
        self * Expr::int(rhs)
    }
}

impl std::ops::Div<i64> for Expr {
    type Output = Expr;
    fn div(self, rhs: i64) -> Expr {
        self / Expr::int(rhs)
    }
}

impl std::ops::Mul<Expr> for i64 {
    type Output = Expr;
    fn mul(self, rhs: Expr) -> Expr {
        Expr::int(self) * rhs
    }
}

impl std::ops::Add<Expr> for i64 {
    type Output = Expr;
    fn add(self, rhs: Expr) -> Expr {
        Expr::int(self) + rhs
    }
}

impl std::ops::Div<Expr> for i64 {
    type Output = Expr;
    fn div(self, rhs: Expr) -> Expr {
        Expr::int(self) / rhs
    }
}

impl std::ops::Sub<Expr> for i64 {
    type Output = Expr;
    fn sub(self, rhs: Expr) -> Expr {
        Expr::int(self) - rhs
    }
}

impl std::ops::AddAssign for Expr {
    fn add_assign(&mut self, rhs: Expr) {
        *self = *self + rhs;
    }
}

impl std::ops::SubAssign for Expr {
    fn sub_assign(&mut self, rhs: Expr) {
        *self = *self - rhs;
    }
}

impl std::ops::MulAssign for Expr {
    fn mul_assign(&mut self, rhs: Expr) {
        *self = *self * rhs;
    }
}

impl std::iter::Sum for Expr {
    fn sum<I: Iterator<Item = Expr>>(iter: I) -> Expr {
        Expr::add_all(iter)
    }
}

impl std::iter::Product for Expr {
    fn product<I: Iterator<Item = Expr>>(iter: I) -> Expr {
        Expr::mul_all(iter)
    }
}

impl From<i64> for Expr {
    fn from(n: i64) -> Expr {
        Expr::int(n)
    }
}

impl From<Number> for Expr {
    fn from(n: Number) -> Expr {
        Expr::number(n)
    }
}

/// `sin`, `cos` or `tan` of an inverse trigonometric function, as an algebraic expression: the
/// identities hold on the inverse's whole domain (`asin`, `acos` on [−1, 1], where
/// `cos(asin u) = √(1 − u²)` ≥ 0; `atan` everywhere; `atan2(y, x)` away from the origin),
/// so equilibria in closed form read `√(1 − u²)`, not `cos(asin(u))`.
fn trig_of_inverse(f: Func, arg: Expr) -> Option<Expr> {
    let Node::Func(inverse, args) = arg.node() else {
        return None;
    };
    let one = Expr::one();
    let e = match (f, *inverse, &args[..]) {
        (Func::Sin, Func::Asin, [u])
        | (Func::Cos, Func::Acos, [u])
        | (Func::Tan, Func::Atan, [u]) => *u,
        (Func::Cos, Func::Asin, [u]) | (Func::Sin, Func::Acos, [u]) => (one - u.powi(2)).sqrt(),
        (Func::Tan, Func::Asin, [u]) => *u / (one - u.powi(2)).sqrt(),
        (Func::Tan, Func::Acos, [u]) => (one - u.powi(2)).sqrt() / *u,
        (Func::Sin, Func::Atan, [u]) => *u / (one + u.powi(2)).sqrt(),
        (Func::Cos, Func::Atan, [u]) => one / (one + u.powi(2)).sqrt(),
        (Func::Sin, Func::Atan2, [y, x]) => *y / (x.powi(2) + y.powi(2)).sqrt(),
        (Func::Cos, Func::Atan2, [y, x]) => *x / (x.powi(2) + y.powi(2)).sqrt(),
        (Func::Tan, Func::Atan2, [y, x]) => *y / *x,
        _ => return None,
    };
    Some(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trigonometry_of_an_inverse_is_algebraic_and_keeps_its_value() {
        let (u, y, x) = (Expr::symbol("u"), Expr::symbol("y"), Expr::symbol("x"));
        let one = Expr::one();
        assert_eq!(u.asin().sin(), u);
        assert_eq!(u.acos().cos(), u);
        assert_eq!(u.atan().tan(), u);
        assert_eq!(u.asin().cos(), (one - u.powi(2)).sqrt());
        assert_eq!(u.atan().cos(), one / (one + u.powi(2)).sqrt());
        let cases = [
            u.asin().cos(),
            u.asin().tan(),
            u.acos().sin(),
            u.acos().tan(),
            u.atan().sin(),
            u.atan().cos(),
            Expr::atan2(y, x).sin(),
            Expr::atan2(y, x).cos(),
            Expr::atan2(y, x).tan(),
        ];
        let expected = |k: usize, u: f64, y: f64, x: f64| match k {
            0 => u.asin().cos(),
            1 => u.asin().tan(),
            2 => u.acos().sin(),
            3 => u.acos().tan(),
            4 => u.atan().sin(),
            5 => u.atan().cos(),
            6 => y.atan2(x).sin(),
            7 => y.atan2(x).cos(),
            _ => y.atan2(x).tan(),
        };
        // On the whole domain: both signs of u, every quadrant of (x, y).
        for (uv, yv, xv) in [(0.3, 1.2, -0.7), (-0.8, -0.4, -2.0), (0.95, -1.1, 0.6)] {
            for (k, e) in cases.iter().enumerate() {
                let got = e
                    .eval(&|s: Symbol| {
                        Some(match s.name() {
                            "u" => uv,
                            "y" => yv,
                            _ => xv,
                        })
                    })
                    .unwrap();
                let want = expected(k, uv, yv, xv);
                assert!(
                    (got - want).abs() < 1e-12 * want.abs().max(1.0),
                    "{k}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn hash_consing_shares_equal_nodes() {
        let x = Expr::symbol("x");
        let y = Expr::symbol("y");
        assert_eq!(x + y, y + x);
        assert_eq!((x + y) * (x + y), (y + x).powi(2));
        assert_ne!(Expr::symbol("x"), Expr::coordinate("x"));
    }

    #[test]
    fn nodes_found_from_their_parts_are_the_nodes_built_whole() {
        let x = Expr::symbol("intern_parts_x");
        let y = Expr::symbol("intern_parts_y");
        let two = Expr::int(2);
        // Built whole first, then looked up from parts …
        let whole = intern(Node::Mul(vec![two, x, y].into()));
        assert_eq!(intern_compound(Compound::Mul, &[two, x, y]), whole);
        // … and made from parts first, then looked up whole.
        let parts = intern_compound(Compound::Add, &[two, x, y]);
        assert_eq!(intern(Node::Add(vec![two, x, y].into())), parts);
        assert_ne!(parts, whole);
        let f = intern_compound(Compound::Func(Func::Sin), &[x]);
        assert_eq!(f, intern(Node::Func(Func::Sin, vec![x].into())));
        assert_ne!(f, intern_compound(Compound::Func(Func::Cos), &[x]));
        let p = intern_compound(Compound::Pow, &[x, two]);
        assert_eq!(p, intern(Node::Pow([x, two])));
        assert_eq!(p.children(), &[x, two]);
    }

    #[test]
    fn constructors_fold_like_terms_and_bases() {
        let x = Expr::symbol("x");
        assert_eq!(x + x, 2 * x);
        assert_eq!(x * x, x.powi(2));
        assert_eq!(x - x, Expr::zero());
        assert_eq!(x / x, Expr::one());
        assert_eq!(Expr::int(4).sqrt(), Expr::int(2));
        assert_eq!((2 * x).powi(2), 4 * x.powi(2));
        assert_eq!(Expr::int(0).sin(), Expr::zero());
    }
}
