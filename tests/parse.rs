//! The parser: every construct's AST shape and spans, precedence, the `in` keyword vs
//! the inch unit, and the wording and placement of syntax errors.

use dieface::diag::Diagnostic;
use dieface::syntax::ast::{
    BinaryOp, DeclBody, Expr, ExprKind, FieldValue, File, Item, SketchCommandKind, UnaryOp, Unit,
};
use dieface::syntax::print::{format_number, print_ast};
use dieface::syntax::{parse, FileId};
use proptest::prelude::*;

const F: FileId = FileId(7);

fn ok(src: &str) -> File {
    match parse(src, F) {
        Ok(f) => f,
        Err(d) => panic!("{src:?} failed: {} at {:?}", d.message, d.primary.span),
    }
}

fn err(src: &str) -> Diagnostic {
    match parse(src, F) {
        Ok(f) => panic!("{src:?} parsed:\n{}", print_ast(&f, src)),
        Err(d) => {
            assert_eq!(d.code, "die::syntax");
            assert_eq!(d.primary.span.file, F);
            d
        }
    }
}

/// The expression of `let x = <src>`.
fn expr(src: &str) -> Expr {
    let text = format!("let x = {src}");
    let file = ok(&text);
    match file.items.into_iter().next() {
        Some(Item::Decl(d)) => match d.body {
            DeclBody::Expr(e) => e,
            DeclBody::Block(_) => panic!("block"),
        },
        _ => panic!("not a declaration"),
    }
}

/// A compact s-expression of an expression, for precedence checks.
fn sx(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number { value, unit } => match unit {
            Some(u) => format!("{}{}", format_number(*value), u.node.symbol()),
            None => format_number(*value),
        },
        ExprKind::Str(s) => format!("{s:?}"),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Name(n) => n.clone(),
        ExprKind::List(xs) => format!("[{}]", xs.iter().map(sx).collect::<Vec<_>>().join(" ")),
        ExprKind::Comprehension {
            body,
            var,
            iter,
            cond,
        } => match cond {
            Some(c) => format!(
                "[{} for {} in {} if {}]",
                sx(body),
                var.node,
                sx(iter),
                sx(c)
            ),
            None => format!("[{} for {} in {}]", sx(body), var.node, sx(iter)),
        },
        ExprKind::Tuple(xs) => format!(
            "(tuple {})",
            xs.iter().map(sx).collect::<Vec<_>>().join(" ")
        ),
        ExprKind::Record(fs) => {
            format!(
                "{{{}}}",
                fs.iter()
                    .map(|(k, v)| format!("{}: {}", k.node, sx(v)))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
        ExprKind::Field { target, name } => format!("(. {} {})", sx(target), name.node),
        ExprKind::Index { target, index } => format!("(idx {} {})", sx(target), sx(index)),
        ExprKind::Call { callee, args } => {
            let args: Vec<String> = args
                .iter()
                .map(|a| match &a.name {
                    Some(n) => format!("{}: {}", n.node, sx(&a.value)),
                    None => sx(&a.value),
                })
                .collect();
            format!("(call {} {})", sx(callee), args.join(" ")).replace(" )", ")")
        }
        ExprKind::Pipe { input, call } => format!("(|> {} {})", sx(input), sx(call)),
        ExprKind::Unary { op, operand } => {
            let o = if op.node == UnaryOp::Neg {
                "neg"
            } else {
                "not"
            };
            format!("({o} {})", sx(operand))
        }
        ExprKind::Binary { op, lhs, rhs } => {
            format!("({} {} {})", op.node.symbol(), sx(lhs), sx(rhs))
        }
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => format!("(if {} {} {})", sx(cond), sx(then), sx(otherwise)),
        ExprKind::Lambda { params, body } => {
            let ps: Vec<String> = params
                .iter()
                .map(|p| match &p.default {
                    Some(d) => format!("{}={}", p.name.node, sx(d)),
                    None => p.name.node.clone(),
                })
                .collect();
            format!("(fn ({}) {})", ps.join(" "), sx(body))
        }
        ExprKind::Sketch { view, commands } => format!("(sketch {} {})", sx(view), commands.len()),
    }
}

fn slice(src: &str, span: dieface::syntax::Span) -> &str {
    &src[span.range()]
}

// ---------------------------------------------------------------------------------------
// Constructs

#[test]
fn number_with_unit_has_exact_spans() {
    let src = "let width = 12 mm";
    let f = ok(src);
    let Item::Decl(d) = &f.items[0] else { panic!() };
    assert_eq!(d.kind.node, "let");
    assert_eq!(slice(src, d.kind.span), "let");
    assert_eq!(d.name.node, "width");
    assert_eq!((d.name.span.start, d.name.span.end), (4, 9));
    assert_eq!((d.span.start, d.span.end), (0, 17));
    let DeclBody::Expr(e) = &d.body else { panic!() };
    let ExprKind::Number {
        value,
        unit: Some(unit),
    } = &e.kind
    else {
        panic!("{e:?}")
    };
    assert_eq!(*value, 12.0);
    assert_eq!(unit.node, Unit::Mm);
    assert_eq!((unit.span.start, unit.span.end), (15, 17));
    assert_eq!(unit.span.file, F);
    assert_eq!((e.span.start, e.span.end), (12, 17));
    assert_eq!(f.span.file, F);
    assert_eq!((f.span.start, f.span.end), (0, src.len() as u32));
}

#[test]
fn number_forms_and_units() {
    assert_eq!(sx(&expr("12")), "12");
    assert_eq!(sx(&expr("12.5")), "12.5");
    assert_eq!(sx(&expr("1e-3")), "0.001");
    assert_eq!(sx(&expr("2.5E2 m")), "250m");
    assert_eq!(sx(&expr("12mm")), "12mm");
    assert_eq!(sx(&expr("3 cm")), "3cm");
    assert_eq!(sx(&expr("3 m")), "3m");
    assert_eq!(sx(&expr("1 in")), "1in");
    assert_eq!(sx(&expr("90deg")), "90deg");
    assert_eq!(sx(&expr("1.5 rad")), "1.5rad");
    assert_eq!(sx(&expr("50 %")), "50%");
    assert_eq!(sx(&expr("50%")), "50%");
    // Longest unit first (`mm` is not `m` then `m`).
    assert_eq!(sx(&expr("f(2 mm, 3 m)")), "(call f 2mm 3m)");
}

#[test]
fn unit_not_glued_to_identifier() {
    // `2 max` is the number 2 and then the name `max`: here as the next field's word.
    let src = "feature f { a = 2 max = 3 }";
    let f = ok(src);
    let Item::Decl(d) = &f.items[0] else { panic!() };
    let DeclBody::Block(b) = &d.body else {
        panic!()
    };
    assert_eq!(b.fields.len(), 2);
    assert_eq!(b.fields[1].path[0].node, "max");
    let FieldValue::Expr(e) = &b.fields[0].value else {
        panic!()
    };
    assert_eq!(sx(e), "2");
    // And `m` at the start of the next line is a field, not metres.
    let f = ok("feature f {\n  a = 2\n  m = 3\n}");
    let Item::Decl(d) = &f.items[0] else { panic!() };
    let DeclBody::Block(b) = &d.body else {
        panic!()
    };
    assert_eq!(b.fields.len(), 2);
    assert_eq!(b.fields[1].path[0].node, "m");
}

#[test]
fn in_is_inch_after_a_number_and_keyword_elsewhere() {
    let e = expr("[x * 2 in for x in xs]");
    assert_eq!(sx(&e), "[(* x 2in) for x in xs]");
    let ExprKind::Comprehension { body, var, .. } = &e.kind else {
        panic!()
    };
    assert_eq!(var.node, "x");
    let ExprKind::Binary { rhs, .. } = &body.kind else {
        panic!()
    };
    let ExprKind::Number { unit: Some(u), .. } = &rhs.kind else {
        panic!()
    };
    assert_eq!(u.node, Unit::In);
    assert_eq!(
        sx(&expr("[2 for i in range(3)]")),
        "[2 for i in (call range 3)]"
    );
    assert_eq!(
        sx(&expr("[p.x for p in pts if p.y > 0 mm]")),
        "[(. p x) for p in pts if (> (. p y) 0mm)]"
    );
}

#[test]
fn strings_bools_names() {
    assert_eq!(
        sx(&expr(r#""a \"q\" \\ \n \t""#)),
        format!("{:?}", "a \"q\" \\ \n \t")
    );
    assert_eq!(sx(&expr("true")), "true");
    assert_eq!(sx(&expr("false")), "false");
    assert_eq!(sx(&expr("truex")), "truex");
    assert_eq!(sx(&expr("input")), "input");
    assert_eq!(sx(&expr("_a1")), "_a1");
}

#[test]
fn lists_tuples_records() {
    assert_eq!(sx(&expr("[]")), "[]");
    assert_eq!(sx(&expr("[a, b, c,]")), "[a b c]");
    assert_eq!(sx(&expr("(a)")), "a");
    assert_eq!(sx(&expr("(a, b)")), "(tuple a b)");
    assert_eq!(sx(&expr("(a, b, c,)")), "(tuple a b c)");
    assert_eq!(sx(&expr("{}")), "{}");
    assert_eq!(
        sx(&expr("{ a: 1, tangent: 2 mm, }")),
        "{a: 1, tangent: 2mm}"
    );
    // A parenthesised expression spans its parentheses.
    let src = "let x = (a + b) * c";
    let f = ok(src);
    let Item::Decl(d) = &f.items[0] else { panic!() };
    let DeclBody::Expr(e) = &d.body else { panic!() };
    assert_eq!(slice(src, e.span), "(a + b) * c");
    let ExprKind::Binary { lhs, .. } = &e.kind else {
        panic!()
    };
    assert_eq!(slice(src, lhs.span), "(a + b)");
}

#[test]
fn precedence() {
    assert_eq!(sx(&expr("a + b * c")), "(+ a (* b c))");
    assert_eq!(sx(&expr("a * b + c")), "(+ (* a b) c)");
    assert_eq!(sx(&expr("a - b - c")), "(- (- a b) c)");
    assert_eq!(sx(&expr("a / b / c")), "(/ (/ a b) c)");
    assert_eq!(sx(&expr("-x.y")), "(neg (. x y))");
    assert_eq!(sx(&expr("-x * y")), "(* (neg x) y)");
    assert_eq!(sx(&expr("- -x")), "(neg (neg x))");
    assert_eq!(sx(&expr("not a and b")), "(and (not a) b)");
    assert_eq!(sx(&expr("not a == b")), "(not (== a b))");
    assert_eq!(sx(&expr("a or b and c")), "(or a (and b c))");
    assert_eq!(sx(&expr("a + 1 < b * 2")), "(< (+ a 1) (* b 2))");
    assert_eq!(
        sx(&expr("a <= b and c != d or e >= f")),
        "(or (and (<= a b) (!= c d)) (>= e f))"
    );
    assert_eq!(sx(&expr("a |> f(b) |> g")), "(|> (|> a (call f b)) g)");
    assert_eq!(sx(&expr("a + 1 |> f")), "(|> (+ a 1) f)");
    assert_eq!(sx(&expr("a or b |> f")), "(|> (or a b) f)");
    assert_eq!(
        sx(&expr("xs |> profiles.offset(2 mm)")),
        "(|> xs (call (. profiles offset) 2mm))"
    );
    assert_eq!(
        sx(&expr("a.b[0](c)(d: 1,)")),
        "(call (call (idx (. a b) 0) c) d: 1)"
    );
    assert_eq!(sx(&expr("f()")), "(call f)");
    assert_eq!(sx(&expr("c.tangent")), "(. c tangent)");
}

#[test]
fn if_and_lambda_extend_right() {
    assert_eq!(
        sx(&expr("1 + if c then 2 else 3 + 4")),
        "(+ 1 (if c 2 (+ 3 4)))"
    );
    assert_eq!(
        sx(&expr("if a < b then a else b |> f")),
        "(if (< a b) a (|> b f))"
    );
    assert_eq!(
        sx(&expr("fn(x, y = 1 mm) => x + y")),
        "(fn (x y=1mm) (+ x y))"
    );
    assert_eq!(
        sx(&expr("map(xs, fn(p) => p.x)")),
        "(call map xs (fn (p) (. p x)))"
    );
    assert_eq!(
        sx(&expr("if a then if b then 1 else 2 else 3")),
        "(if a (if b 1 2) 3)"
    );
}

#[test]
fn binary_and_unary_spans() {
    let src = "let x = -a.b + c * 2";
    let f = ok(src);
    let Item::Decl(d) = &f.items[0] else { panic!() };
    let DeclBody::Expr(e) = &d.body else { panic!() };
    assert_eq!(slice(src, e.span), "-a.b + c * 2");
    let ExprKind::Binary { op, lhs, rhs } = &e.kind else {
        panic!()
    };
    assert_eq!(op.node, BinaryOp::Add);
    assert_eq!(slice(src, op.span), "+");
    assert_eq!(slice(src, lhs.span), "-a.b");
    assert_eq!(slice(src, rhs.span), "c * 2");
    let ExprKind::Unary { op, operand } = &lhs.kind else {
        panic!()
    };
    assert_eq!(slice(src, op.span), "-");
    assert_eq!(slice(src, operand.span), "a.b");
}

#[test]
fn items() {
    let src = "import \"std/profiles\" as profiles\nunits mm deg\nfn ramp(a, b = 2 mm, c,) = a + b\nlet w = 1";
    let f = ok(src);
    assert_eq!(f.items.len(), 4);
    let Item::Import(i) = &f.items[0] else {
        panic!()
    };
    assert_eq!(i.path.node, "std/profiles");
    assert_eq!(slice(src, i.path.span), "\"std/profiles\"");
    assert_eq!(i.alias.node, "profiles");
    assert_eq!(slice(src, i.span), "import \"std/profiles\" as profiles");
    let Item::Units(u) = &f.items[1] else {
        panic!()
    };
    assert_eq!(
        u.units.iter().map(|u| u.node).collect::<Vec<_>>(),
        vec![Unit::Mm, Unit::Deg]
    );
    assert_eq!(slice(src, u.units[1].span), "deg");
    assert_eq!(slice(src, u.span), "units mm deg");
    let Item::Function(func) = &f.items[2] else {
        panic!()
    };
    assert_eq!(func.name.node, "ramp");
    assert_eq!(func.params.len(), 3);
    assert_eq!(func.params[1].name.node, "b");
    assert_eq!(sx(func.params[1].default.as_ref().unwrap()), "2mm");
    assert!(func.params[2].default.is_none());
    assert_eq!(sx(&func.body), "(+ a b)");
    assert_eq!(slice(src, func.span), "fn ramp(a, b = 2 mm, c,) = a + b");
}

#[test]
fn separators_and_comments_everywhere() {
    let src =
        "; /* lead */ let a = 1 ; ; // tail\nlet/*x*/b/*y*/=/*z*/[ 1 // one\n , 2 /* two */ ] ;\n\
               f g { /* c */ ; x = 1 ; ; y { z = 2 // zz\n } ; } // end";
    let f = ok(src);
    assert_eq!(f.items.len(), 3);
    let Item::Decl(b) = &f.items[1] else { panic!() };
    assert_eq!(b.name.node, "b");
    assert_eq!(
        slice(src, b.span),
        "let/*x*/b/*y*/=/*z*/[ 1 // one\n , 2 /* two */ ]"
    );
    let Item::Decl(g) = &f.items[2] else { panic!() };
    // Spans end at the last token, not at trailing trivia.
    let DeclBody::Block(blk) = &g.body else {
        panic!()
    };
    assert_eq!(blk.fields.len(), 2);
    assert_eq!(slice(src, blk.fields[0].span), "x = 1");
    assert_eq!(slice(src, blk.fields[1].span), "y { z = 2 // zz\n }");
    let a = ok("let a = 1 // c");
    let Item::Decl(a) = &a.items[0] else { panic!() };
    assert_eq!(a.span.end, 9);
    assert!(ok("").items.is_empty());
    assert!(ok("// only a comment").items.is_empty());
    assert!(ok("\u{FEFF}let a = 1").items.len() == 1);
}

#[test]
fn nested_blocks_and_multiword_fields() {
    let src = "punch_opening pol {\n  side front = sketch(side_xz) { from (0, 0) }\n  corners { tangent = 60 mm\n inner { r = 1 } }\n}";
    let f = ok(src);
    let Item::Decl(d) = &f.items[0] else { panic!() };
    assert_eq!(d.kind.node, "punch_opening");
    let DeclBody::Block(b) = &d.body else {
        panic!()
    };
    assert_eq!(slice(src, b.span), &src[18..]);
    assert_eq!(
        b.fields[0]
            .path
            .iter()
            .map(|p| p.node.as_str())
            .collect::<Vec<_>>(),
        ["side", "front"]
    );
    assert_eq!(slice(src, b.fields[0].path[1].span), "front");
    let FieldValue::Block(corners) = &b.fields[1].value else {
        panic!()
    };
    assert_eq!(corners.fields[0].path[0].node, "tangent");
    let FieldValue::Block(inner) = &corners.fields[1].value else {
        panic!()
    };
    assert_eq!(slice(src, inner.span), "{ r = 1 }");
}

#[test]
fn sketch_commands() {
    let src = "let s = sketch(top) {\n  from (0, 0)\n  line to (10 mm, 0); arc to (20, 10) through (15, 2)\n  \
               tangent arc to (30, 0) spline through [p, q] tangent spline through pts\n  fillet 5 mm\n  close\n}";
    let f = ok(src);
    let Item::Decl(d) = &f.items[0] else { panic!() };
    let DeclBody::Expr(e) = &d.body else { panic!() };
    assert_eq!(slice(src, e.span), &src[8..]);
    let ExprKind::Sketch { view, commands } = &e.kind else {
        panic!()
    };
    assert_eq!(sx(view), "top");
    assert_eq!(commands.len(), 8);
    let texts: Vec<&str> = commands.iter().map(|c| slice(src, c.span)).collect();
    assert_eq!(
        texts,
        [
            "from (0, 0)",
            "line to (10 mm, 0)",
            "arc to (20, 10) through (15, 2)",
            "tangent arc to (30, 0)",
            "spline through [p, q]",
            "tangent spline through pts",
            "fillet 5 mm",
            "close"
        ]
    );
    assert!(matches!(&commands[0].kind, SketchCommandKind::From(p) if sx(p) == "(tuple 0 0)"));
    assert!(matches!(&commands[1].kind, SketchCommandKind::LineTo(p) if sx(p) == "(tuple 10mm 0)"));
    assert!(
        matches!(&commands[2].kind, SketchCommandKind::ArcThrough { to, through } if sx(to) == "(tuple 20 10)" && sx(through) == "(tuple 15 2)")
    );
    assert!(matches!(
        &commands[3].kind,
        SketchCommandKind::TangentArcTo(_)
    ));
    assert!(
        matches!(&commands[4].kind, SketchCommandKind::Spline { tangent: false, through } if sx(through) == "[p q]")
    );
    assert!(matches!(
        &commands[5].kind,
        SketchCommandKind::Spline { tangent: true, .. }
    ));
    assert!(matches!(&commands[6].kind, SketchCommandKind::Fillet(r) if sx(r) == "5mm"));
    assert!(matches!(&commands[7].kind, SketchCommandKind::Close));
    assert_eq!(sx(&expr("sketch(v) {}")), "(sketch v 0)");
}

#[test]
fn printer_is_stable_and_located() {
    let src = "units mm\nlet w = 550.0000001 mm\nlet t = 1 / 3";
    let out = print_ast(&ok(src), src);
    let expected = "File (3 items) @1:1..3:14\n  Units mm @1:1..1:9\n  Decl let w @2:1..2:23\n    \
                    Number 550 mm (unit @2:21..2:23) @2:9..2:23\n  Decl let t @3:1..3:14\n    \
                    Binary / @3:9..3:14\n      Number 1 @3:9..3:10\n      Number 3 @3:13..3:14\n";
    assert_eq!(out, expected);
    assert_eq!(format_number(1.0 / 3.0), "0.333333");
    assert_eq!(format_number(-0.01), "-0.01");
    assert_eq!(format_number(1e-9), "1e-9");
    assert_eq!(format_number(123456789.0), "123456789");
}

// ---------------------------------------------------------------------------------------
// Errors: message text and span

fn at<'a>(src: &'a str, d: &Diagnostic) -> &'a str {
    &src[d.primary.span.range()]
}

#[test]
fn error_missing_close_paren() {
    let src = "let x = f(a, b\n";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected `,` or `)` to close the argument list, found the end of the file"
    );
    assert_eq!(d.primary.message, "the file ends here");
    // Right after the last token.
    assert_eq!(d.primary.span.start, 14);
    assert_eq!(d.secondary[0].span.start, 9);
    assert!(d.secondary[0].message.contains("not closed"));
    // Without a trailing newline: the last character.
    let d = err("let x = (1, 2");
    assert_eq!(
        d.message,
        "expected `)` to close the parenthesis, found the end of the file"
    );
    assert_eq!((d.primary.span.start, d.primary.span.end), (12, 13));
}

#[test]
fn error_missing_comma_between_arguments() {
    let src = "let x = f(a b)";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected `,` or `)` to close the argument list, found `b`"
    );
    assert_eq!(at(src, &d), "b");
    assert!(d.help.unwrap().contains("is a `,` missing before `b`"));
    let d = err("let x = [1 2]");
    assert_eq!(
        d.message,
        "expected `,` or `]` to close the list, found `2`"
    );
}

#[test]
fn error_mismatched_bracket_points_at_opener() {
    let src = "let x = f(a]";
    let d = err(src);
    assert!(
        d.message
            .starts_with("expected `,` or `)` to close the argument list"),
        "{}",
        d.message
    );
    assert_eq!(at(src, &d), "]");
    assert_eq!(&src[d.secondary[0].span.range()], "(");
}

#[test]
fn error_unknown_character() {
    let src = "let x = 5 $ 3";
    let d = err(src);
    assert_eq!(d.message, "unknown character `$`");
    assert_eq!(at(src, &d), "$");
    let src = "let s = 'abc'";
    let d = err(src);
    assert_eq!(d.message, "unknown character `'`");
    assert!(d.help.unwrap().contains("double quotes"));
    let src = "let x = 1 # comment";
    assert!(err(src).help.unwrap().contains("//"));
    let src = "let x = a ≤ b";
    let d = err(src);
    assert_eq!(at(src, &d), "≤");
}

#[test]
fn error_bad_unit_word() {
    let src = "let x = 5 mmm";
    let d = err(src);
    assert_eq!(d.message, "`mmm` is not a unit");
    assert_eq!(at(src, &d), "mmm");
    assert_eq!(&src[d.secondary[0].span.range()], "5");
    assert!(d.help.unwrap().starts_with("did you mean `mm`?"));
    let src = "let x = 5degs\nlet y = 2";
    let d = err(src);
    assert_eq!(d.message, "`degs` is not a unit");
    assert_eq!(at(src, &d), "degs");
    let src = "let x = f(5 inch, 2)";
    assert_eq!(at(src, &err(src)), "inch");
}

#[test]
fn error_missing_declaration_name() {
    let src = "let = 5";
    let d = err(src);
    assert_eq!(d.message, "expected a name for the declaration, found `=`");
    assert_eq!(at(src, &d), "=");
    assert!(d.help.unwrap().contains("kind, then its name"));
}

#[test]
fn error_keyword_as_name() {
    let src = "let in = 5";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected a name for the declaration, found the keyword `in`"
    );
    assert_eq!(at(src, &d), "in");
    assert_eq!(
        d.help.as_deref(),
        Some("`in` is a keyword; choose another name")
    );
    let src = "fn f(to) = to";
    let d = err(src);
    assert_eq!(at(src, &d), "to");
    assert_eq!(
        d.help.as_deref(),
        Some("`to` is a keyword; choose another name")
    );
    let src = "let xs = [p for from in ps]";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected a name for the loop variable, found the keyword `from`"
    );
}

#[test]
fn error_chained_comparison() {
    let src = "let ok = a < b < c";
    let d = err(src);
    assert_eq!(d.message, "comparisons cannot be chained");
    assert_eq!(d.primary.span.start, 15);
    assert_eq!(at(src, &d), "<");
    assert_eq!(d.secondary[0].span.start, 11);
    assert!(d.help.unwrap().contains("and"));
    // Parenthesised, it is fine (and evaluates a boolean against c).
    assert_eq!(sx(&expr("(a < b) == c")), "(== (< a b) c)");
}

#[test]
fn error_unterminated_string() {
    let src = "let s = \"abc\nlet t = 1";
    let d = err(src);
    assert_eq!(d.message, "unterminated string");
    assert_eq!(at(src, &d), "\"abc");
    let src = "let s = \"a\\qb\"";
    let d = err(src);
    assert_eq!(d.message, "unknown escape `\\q` in a string");
    assert_eq!(at(src, &d), "\\q");
}

#[test]
fn error_unterminated_block_comment() {
    let src = "let x = 1\n/* never closed\nlet y = 2";
    let d = err(src);
    assert_eq!(d.message, "unterminated block comment");
    assert_eq!(at(src, &d), "/*");
    assert_eq!(d.primary.span.start, 10);
}

#[test]
fn error_missing_equals_in_declaration() {
    let src = "let width 550 mm";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected `=` followed by a value, or a `{` block, found `550`"
    );
    assert_eq!(at(src, &d), "550");
    let src = "let width == 5";
    let d = err(src);
    assert_eq!(at(src, &d), "==");
    assert_eq!(d.help.as_deref(), Some("a declaration takes a single `=`"));
    let src = "f g { depth 40 mm }";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected `=` followed by a value, or a `{` block, found `40`"
    );
}

#[test]
fn error_stray_token_at_top_level() {
    let src = "let x = 5\n)";
    let d = err(src);
    assert_eq!(
        d.message,
        "expected a declaration such as `let width = 550 mm`, found `)`"
    );
    assert_eq!(at(src, &d), ")");
    assert!(d.help.unwrap().contains("no matching `(`"));
    let src = "let x = 5\n+ + 2";
    let d = err(src);
    assert_eq!(at(src, &d), "+");
    let d = err("42");
    assert_eq!(
        d.message,
        "expected a declaration such as `let width = 550 mm`, found `42`"
    );
}

#[test]
fn error_equals_in_condition() {
    let src = "let x = if a = b then 1 else 2";
    let d = err(src);
    assert_eq!(d.message, "expected `then`, found `=`");
    assert_eq!(at(src, &d), "=");
    assert!(d.help.unwrap().contains("`==`"));
}

#[test]
fn error_sketch_and_misc() {
    let src = "let s = sketch(v) { from p\n  foo (1, 2) }";
    let d = err(src);
    assert!(
        d.message
            .starts_with("expected a sketch command (from, line to"),
        "{}",
        d.message
    );
    assert_eq!(at(src, &d), "foo");
    let src = "let s = sketch(v) { line (1, 2) }";
    assert_eq!(err(src).message, "expected `to` and a point, found `(`");
    let src = "let s = sketch(v) { tangent line to p }";
    assert_eq!(
        err(src).message,
        "expected `arc to` or `spline through`, found the keyword `line`"
    );
    let src = "import std as p";
    assert_eq!(
        err(src).message,
        "expected a path in quotes such as \"std/profiles\", found `std`"
    );
    let src = "import \"std/p\" p";
    assert!(err(src).message.starts_with("expected `as`"));
    let src = "units mm furlong";
    let d = err(src);
    assert_eq!(d.message, "`furlong` is not a unit");
    assert_eq!(at(src, &d), "furlong");
    let d = err("units\nlet x = 1");
    assert_eq!(
        d.message,
        "expected a unit (mm, cm, m, in, deg, rad), found the end of the line"
    );
    let d = err("let x = 1 +");
    assert_eq!(
        d.message,
        "expected an expression, found the end of the file"
    );
    let d = err("let f = fn(x) x");
    assert_eq!(
        d.message,
        "expected `=>` followed by the function body, found `x`"
    );
    let d = err("let x = if a then b");
    assert_eq!(d.message, "expected `else`, found the end of the file");
    let d = err("let x = a.");
    assert_eq!(
        d.message,
        "expected a field name, found the end of the file"
    );
    let d = err("let r = { a: 1 b: 2 }");
    assert_eq!(
        d.message,
        "expected `,` or `}` to close the record, found `b`"
    );
    let d = err("let r = { a 1 }");
    assert_eq!(d.message, "expected `:` followed by a value, found `1`");
    let d = err("f g { a = 1");
    assert!(
        d.message.contains("`}` to close the block"),
        "{}",
        d.message
    );
    let d = err("let x = (a,)");
    assert_eq!(d.message, "expected an expression, found `)`");
}

// ---------------------------------------------------------------------------------------
// Robustness

const VALID: &str = r#"// A small die.
import "std/profiles" as profiles
units mm deg

fn ramp(a, b = 2 mm) = a + b * 0.5
param delta = 0.01 mm; let width = 550 mm
let xs = [x * 2 in for x in ys if x > 1]
let p = fn(x, y = 1) => x |> f(y: y) |> g
punch_opening pol {
  top = sketch(top) { from (0, 0); line to (width, 0) arc to (1, 2) through (3, 4)
    tangent arc to p tangent spline through [a, b] fillet 5 mm close }
  side front = -x.y[0] /* c */
  corners { tangent = 60 mm; r = { a: "s\"x", b: if not q and r then 1 else 2 } }
}
"#;

#[test]
fn valid_file_parses_and_truncations_never_panic() {
    ok(VALID);
    for (i, _) in VALID.char_indices() {
        let _ = parse(&VALID[..i], F);
        let _ = parse(&VALID[i..], F);
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let src = format!("let x = {}1{}", "(".repeat(5000), ")".repeat(5000));
    assert!(parse(&src, F).is_err());
    let src = format!("let x = {}1", "-".repeat(5000));
    assert!(parse(&src, F).is_err());
    let src = format!("let x = {}1", "if a then 1 else ".repeat(5000));
    assert!(parse(&src, F).is_err());
    let src = format!("let x = {}1", "fn() => ".repeat(5000));
    assert!(parse(&src, F).is_err());
    // Up to the limit, it parses (on a test thread's small stack).
    let src = format!("let x = {}1{}", "[".repeat(120), "]".repeat(120));
    assert!(parse(&src, F).is_ok());
    let src = format!("let x = {}1{}", "[".repeat(129), "]".repeat(129));
    assert!(err(&src)
        .message
        .contains("nested more than 128 levels deep"));
    let src = format!("let x = {}1", "if a then 1 else -".repeat(60));
    assert!(parse(&src, F).is_ok());
    let src = format!("let x = {}1{}", "f(-".repeat(60), ")".repeat(60));
    assert!(parse(&src, F).is_ok());
    // Many flat negatives and conditions are not nesting.
    let src = "let a = -1 - -2\n".repeat(2000);
    assert!(parse(&src, F).is_ok());
    let src = "let a = [if c then -1 else -2, -3]\n".repeat(2000);
    assert!(parse(&src, F).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let text = String::from_utf8_lossy(&bytes);
        if let Err(d) = parse(&text, F) {
            prop_assert!(d.primary.span.start <= d.primary.span.end);
            prop_assert!(d.primary.span.end as usize <= text.len());
            prop_assert!(text.is_char_boundary(d.primary.span.start as usize));
            prop_assert!(text.is_char_boundary(d.primary.span.end as usize));
        }
    }

    #[test]
    fn token_soup_never_panics(toks in proptest::collection::vec(proptest::sample::select(vec![
        "let", "x", "=", "1", "mm", "in", "for", "(", ")", "[", "]", "{", "}", ",", ";", ":", ".",
        "+", "-", "*", "/", "<", "==", "|>", "=>", "fn", "if", "then", "else", "sketch", "from",
        "line", "to", "\"s\"", "\"", "/*", "*/", "//", "\n", "not", "and", "2.5e3", "%", "é",
    ]), 0..40)) {
        let text = toks.join(" ");
        if let Err(d) = parse(&text, F) {
            prop_assert!(d.primary.span.end as usize <= text.len());
            prop_assert!(text.is_char_boundary(d.primary.span.start as usize));
            prop_assert!(text.is_char_boundary(d.primary.span.end as usize));
        }
        let glued = toks.concat();
        let _ = parse(&glued, F);
    }
}
