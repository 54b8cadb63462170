use super::*;
use proptest::prelude::*;

fn m(expr: &str, recorded: &str) -> bool {
    Lpe::parse(expr)
        .unwrap_or_else(|e| panic!("{expr}: {e}"))
        .matches(recorded)
}

fn col(expr: &str) -> usize {
    match Lpe::parse(expr) {
        Ok(_) => panic!("{expr} parsed"),
        Err(e) => e.column,
    }
}

#[test]
fn the_issues_examples() {
    assert!(m("C<RD>L", "C<RD>L"));
    assert!(!m("C<RD>L", "C<RD><RD>L"));
    assert!(m("C<RD>.+L", "C<RD><RD>L"));
    assert!(!m("C<RD>.+L", "C<RD>L"));
    assert!(m("C<RD>S+L", "C<RD><TS><TS>L"));
    assert!(m("CDS+L", "C<RD><TS><TS>L"));
    assert!(m("C<RD><TS>{2}L", "C<RD><TS><TS>L"));
    assert!(!m("C<RD>L", "C<RD><TS><TS>L"));
    assert!(!m("C<RD>S+L", "C<RD><RG>L"));
}

#[test]
fn letters_match_type_or_scattering() {
    assert!(m("CRL", "C<RD>L") && m("CRL", "C<RS>L") && !m("CRL", "C<TS>L"));
    assert!(m("CTL", "C<TG>L"));
    assert!(m("CGL", "C<RG>L") && m("CGL", "C<TG>L") && !m("CGL", "C<RS>L"));
    assert!(m("CB", "CB") && !m("CL", "CB"));
    assert!(m("<C.><R.><L.>", "C<RD>L"));
    assert!(m("< T S >", "<TS>"));
    assert!(m("C<.D>L", "C<RD>L"));
    assert!(m("C<RD''>L", "C<RD>L") && m("C<RD.>L", "C<RD>L"));
    assert!(!m("C<RD'wall'>L", "C<RD>L"));
}

#[test]
fn sets_complements_alternatives_groups() {
    assert!(m("C[DG]L", "C<RD>L") && m("C[DG]L", "C<TG>L") && !m("C[DG]L", "C<RS>L"));
    assert!(m("C[^S]L", "C<RD>L") && !m("C[^S]L", "C<TS>L"));
    assert!(m("C[^S]*L", "CL") && !m("C[^S]*L", "C<RD><RS>L"));
    assert!(m("C[<RD><TS>]+L", "C<RD><TS>L"));
    assert!(m("C(D|S)L", "C<RS>L") && !m("C(D|S)L", "C<RG>L"));
    assert!(m("CD+L|CB", "CB") && m("CD+L|CB", "C<RD>L") && !m("CD+L|CB", "C<RD>B"));
    assert!(m("C(<RD><TS>)+L", "C<RD><TS><RD><TS>L"));
    assert!(!m("C(<RD><TS>)+L", "C<RD><TS><RD>L"));
}

#[test]
fn repetition_bounds() {
    let e = |n: usize| format!("C{}L", "<RD>".repeat(n));
    for n in 0..6 {
        assert_eq!(m("CD{2,3}L", &e(n)), (2..=3).contains(&n), "{n}");
        assert_eq!(m("CD{2}L", &e(n)), n == 2, "{n}");
        assert_eq!(m("CD{2,}L", &e(n)), n >= 2, "{n}");
        assert_eq!(m("CD?L", &e(n)), n <= 1, "{n}");
        assert!(m("CD*L", &e(n)), "{n}");
        assert_eq!(m("CD+L", &e(n)), n >= 1, "{n}");
    }
}

#[test]
fn dot_and_anchoring() {
    assert!(m(".", "C") && !m(".", "CB") && m("..", "CB"));
    assert!(m(".*", "") && m(".*", "C<RD><TS>L"));
    // anchored at both ends: a prefix or a suffix is not a match
    assert!(!m("C<RD>", "C<RD>L") && !m("<RD>L", "C<RD>L"));
    assert!(m("C.*", "C<RD>L"));
}

#[test]
fn unknown_recorded_events_match_nothing() {
    assert!(!m(".*", "C<XD>L"));
    assert!(!m(".*", "C<RD"));
    assert_eq!(recorded_events("C<RD>L").map(|v| v.len()), Some(3));
    assert_eq!(recorded_events("Cq"), None);
}

#[test]
fn errors_name_the_column() {
    assert_eq!(col("C<RD"), 2);
    assert_eq!(col("C{2,1}"), 2);
    assert_eq!(col("C["), 2);
    assert_eq!(col("Cx"), 2);
    assert_eq!(col(""), 1);
    assert_eq!(col("C)"), 2);
    assert_eq!(col("C(D"), 2);
    assert_eq!(col("C<XD>"), 3);
    assert_eq!(col("C<RX>"), 4);
    assert_eq!(col("C<RD'a>"), 5);
    assert_eq!(col("*"), 1);
    assert_eq!(col("C|"), 3);
    assert_eq!(col("C{"), 3);
    assert_eq!(col("C{2000}"), 3);
    assert_eq!(col("C[]"), 3);
    assert_eq!(col("C()"), 3);
    // deep nesting and huge repetitions are errors, not a stack overflow or a panic
    assert_eq!(col(&"(".repeat(100_000)), 65);
    let nested = format!("{}C{}", "(".repeat(64), ")".repeat(64));
    assert!(m(&nested, "C"));
    assert_eq!(col("((.{1000}){1000}){1000}"), 1);
    let e = Lpe::parse("C{2,1}").unwrap_err();
    assert_eq!(
        e.to_string(),
        "light path expression, column 2: repetition {2,1}: 2 > 1"
    );
}

/// A recorded string of the path tracer's alphabet.
fn recorded() -> impl Strategy<Value = String> {
    let mid = prop::sample::select(vec!["<RD>", "<RS>", "<TS>", "<RG>", "<TG>"]);
    (
        prop::collection::vec(mid, 0..8),
        prop::sample::select(vec!["L", "B", ""]),
    )
        .prop_map(|(v, end)| format!("C{}{end}", v.concat()))
}

proptest! {
    #[test]
    fn dot_star_matches_everything(s in recorded()) {
        prop_assert!(m(".*", &s));
    }

    #[test]
    fn a_literal_matches_exactly_its_string(a in recorded(), b in recorded()) {
        let lpe = Lpe::parse(&a).unwrap();
        prop_assert!(lpe.matches(&a));
        prop_assert_eq!(lpe.matches(&b), a == b);
    }
}
