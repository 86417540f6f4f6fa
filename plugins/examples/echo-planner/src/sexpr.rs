//! A minimal s-expression reader for PDDL text: symbols and nested lists, `;` comments.

use std::fmt;

/// A symbol or a parenthesised list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Expression {
    Symbol(String),
    List(Vec<Expression>),
}

impl fmt::Display for Expression {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expression::Symbol(symbol) => formatter.write_str(symbol),
            Expression::List(items) => {
                formatter.write_str("(")?;
                for (index, item) in items.iter().enumerate() {
                    if index > 0 {
                        formatter.write_str(" ")?;
                    }
                    write!(formatter, "{item}")?;
                }
                formatter.write_str(")")
            }
        }
    }
}

/// Reads exactly one expression from `text`.
pub(crate) fn parse(text: &str) -> Result<Expression, String> {
    let mut stack: Vec<Vec<Expression>> = vec![Vec::new()];
    for line in text.lines() {
        let code = line.split(';').next().unwrap_or_default();
        let spaced = code.replace('(', " ( ").replace(')', " ) ");
        for token in spaced.split_whitespace() {
            match token {
                "(" => stack.push(Vec::new()),
                ")" => {
                    let list = stack.pop().filter(|_| !stack.is_empty()).ok_or("unbalanced `)`")?;
                    if let Some(parent) = stack.last_mut() {
                        parent.push(Expression::List(list));
                    }
                }
                symbol => match stack.last_mut() {
                    Some(top) => top.push(Expression::Symbol(symbol.to_string())),
                    None => return Err("unbalanced `)`".to_string()),
                },
            }
        }
    }
    match (stack.len(), stack.pop()) {
        (1, Some(mut top)) if top.len() == 1 => Ok(top.remove(0)),
        (1, Some(top)) if top.is_empty() => Err("the text is empty".to_string()),
        (1, Some(_)) => Err("more than one top-level expression".to_string()),
        _ => Err("unbalanced `(`: the text ends inside a list".to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_nested_lists_and_skips_comments() {
        let expression = parse("(a (b c) ; note (\n d)").unwrap();
        assert_eq!(expression.to_string(), "(a (b c) d)");
    }

    #[test]
    fn refuses_unbalanced_text() {
        assert!(parse("(a (b)").unwrap_err().contains("unbalanced `(`"));
        assert!(parse("(a))").unwrap_err().contains("unbalanced `)`"));
        assert!(parse("a b").unwrap_err().contains("more than one"));
        assert!(parse("  ").unwrap_err().contains("empty"));
    }
}
