//! A minimal markdown-to-HTML converter for report sections.
//!
//! Blocks: ATX headings (`#` to `######`, shifted down one level because each section already
//! has an `<h2>` title), paragraphs, pipe tables with a `|---|:--:|` separator row (alignment
//! honoured), flat bullet (`-`, `*`, `+`) and numbered (`1.`) lists, fenced code blocks, `---`
//! rules. Inline: `` `code` ``, `**strong**`, `*emphasis*`, `[text](url)` links and `![alt](src)`
//! images (resolved by the caller, so they can be embedded). Everything else is text, escaped.

/// Escapes `& < > "` for HTML text and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// Converts markdown to HTML; `image(src, alt)` returns the HTML for an image reference.
pub fn to_html(markdown: &str, image: &dyn Fn(&str, &str) -> String) -> String {
    let lines: Vec<&str> = markdown.lines().collect();
    let mut out = String::new();
    let mut paragraph: Vec<&str> = Vec::new();
    let mut i = 0;
    let flush = |paragraph: &mut Vec<&str>, out: &mut String| {
        if !paragraph.is_empty() {
            out.push_str(&format!("<p>{}</p>\n", inline(&paragraph.join(" "), image)));
            paragraph.clear();
        }
    };
    while i < lines.len() {
        let line = lines[i];
        let trimmed = line.trim();
        if trimmed.is_empty() {
            flush(&mut paragraph, &mut out);
            i += 1;
        } else if let Some(fence) = trimmed.strip_prefix("```") {
            flush(&mut paragraph, &mut out);
            let lang = fence.trim();
            let mut code = Vec::new();
            i += 1;
            while i < lines.len() && !lines[i].trim_start().starts_with("```") {
                code.push(lines[i]);
                i += 1;
            }
            i += 1; // the closing fence
            let class = if lang.is_empty() {
                String::new()
            } else {
                format!(" class=\"language-{}\"", escape(lang))
            };
            out.push_str(&format!(
                "<pre><code{class}>{}</code></pre>\n",
                escape(&code.join("\n"))
            ));
        } else if let Some((level, text)) = heading(trimmed) {
            flush(&mut paragraph, &mut out);
            let h = (level + 1).min(6);
            out.push_str(&format!("<h{h}>{}</h{h}>\n", inline(text, image)));
            i += 1;
        } else if is_rule(trimmed) {
            flush(&mut paragraph, &mut out);
            out.push_str("<hr>\n");
            i += 1;
        } else if trimmed.starts_with('|')
            && lines.get(i + 1).is_some_and(|l| separator(l).is_some())
        {
            flush(&mut paragraph, &mut out);
            let align = separator(lines[i + 1]).unwrap_or_default();
            let mut rows = vec![cells(trimmed)];
            i += 2;
            while i < lines.len() && lines[i].trim().starts_with('|') {
                rows.push(cells(lines[i].trim()));
                i += 1;
            }
            out.push_str(&table(&rows, &align, image));
        } else if let Some((ordered, _)) = list_item(trimmed) {
            flush(&mut paragraph, &mut out);
            let tag = if ordered { "ol" } else { "ul" };
            out.push_str(&format!("<{tag}>\n"));
            let mut items: Vec<String> = Vec::new();
            while i < lines.len() {
                let t = lines[i].trim();
                match list_item(t) {
                    Some((o, text)) if o == ordered => items.push(text.to_string()),
                    // An indented line continues the item before it.
                    None if !t.is_empty() && lines[i].starts_with([' ', '\t']) => {
                        if let Some(last) = items.last_mut() {
                            last.push(' ');
                            last.push_str(t);
                        }
                    }
                    _ => break,
                }
                i += 1;
            }
            for item in items {
                out.push_str(&format!("<li>{}</li>\n", inline(&item, image)));
            }
            out.push_str(&format!("</{tag}>\n"));
        } else {
            paragraph.push(trimmed);
            i += 1;
        }
    }
    flush(&mut paragraph, &mut out);
    out
}

fn heading(line: &str) -> Option<(usize, &str)> {
    let level = line.chars().take_while(|&c| c == '#').count();
    let rest = &line[level..];
    ((1..=6).contains(&level) && (rest.is_empty() || rest.starts_with(' ')))
        .then(|| (level, rest.trim().trim_end_matches('#').trim()))
}

fn is_rule(line: &str) -> bool {
    let c: String = line.chars().filter(|c| !c.is_whitespace()).collect();
    c.len() >= 3 && (c.chars().all(|x| x == '-') || c.chars().all(|x| x == '*'))
}

/// `(ordered, text)` of a list item line.
fn list_item(line: &str) -> Option<(bool, &str)> {
    for bullet in ["- ", "* ", "+ "] {
        if let Some(rest) = line.strip_prefix(bullet) {
            return Some((false, rest.trim()));
        }
    }
    let digits = line.chars().take_while(|c| c.is_ascii_digit()).count();
    let rest = &line[digits..];
    (digits > 0 && rest.starts_with(". ")).then(|| (true, rest[2..].trim()))
}

/// The cells of a table row `| a | b |`.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|');
    let inner = inner.strip_suffix('|').unwrap_or(inner);
    inner.split('|').map(|c| c.trim().to_string()).collect()
}

/// Column alignments of a separator row like `|---|:--:|--:|`, or `None` if it is not one.
fn separator(line: &str) -> Option<Vec<&'static str>> {
    let t = line.trim();
    if !t.starts_with('|') {
        return None;
    }
    let cols = cells(t);
    let ok = cols.iter().all(|c| {
        let d = c.trim_matches(':');
        !d.is_empty() && d.chars().all(|x| x == '-')
    });
    ok.then(|| {
        cols.iter()
            .map(|c| match (c.starts_with(':'), c.ends_with(':')) {
                (true, true) => "center",
                (false, true) => "right",
                _ => "",
            })
            .collect()
    })
}

fn table(rows: &[Vec<String>], align: &[&str], image: &dyn Fn(&str, &str) -> String) -> String {
    let mut out = String::from("<table>\n");
    for (r, row) in rows.iter().enumerate() {
        let tag = if r == 0 { "th" } else { "td" };
        if r == 0 {
            out.push_str("<thead>\n");
        } else if r == 1 {
            out.push_str("<tbody>\n");
        }
        out.push_str("<tr>");
        for (c, cell) in row.iter().enumerate() {
            let style = match align.get(c) {
                Some(a) if !a.is_empty() => format!(" style=\"text-align:{a}\""),
                _ => String::new(),
            };
            out.push_str(&format!("<{tag}{style}>{}</{tag}>", inline(cell, image)));
        }
        out.push_str("</tr>\n");
        if r == 0 {
            out.push_str("</thead>\n");
        }
    }
    if rows.len() > 1 {
        out.push_str("</tbody>\n");
    }
    out.push_str("</table>\n");
    out
}

/// Inline formatting of one block's text.
pub fn inline(text: &str, image: &dyn Fn(&str, &str) -> String) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    let find = |from: usize, pat: &[char]| -> Option<usize> {
        (from..chars.len().saturating_sub(pat.len() - 1)).find(|&k| chars[k..k + pat.len()] == *pat)
    };
    let slice = |a: usize, b: usize| chars[a..b].iter().collect::<String>();
    while i < chars.len() {
        let c = chars[i];
        if c == '`' {
            if let Some(end) = find(i + 1, &['`']) {
                out.push_str(&format!("<code>{}</code>", escape(&slice(i + 1, end))));
                i = end + 1;
                continue;
            }
        } else if c == '*' && chars.get(i + 1) == Some(&'*') {
            if let Some(end) = find(i + 2, &['*', '*']).filter(|&e| e > i + 2) {
                out.push_str(&format!(
                    "<strong>{}</strong>",
                    inline(&slice(i + 2, end), image)
                ));
                i = end + 2;
                continue;
            }
        } else if c == '*' && chars.get(i + 1).is_some_and(|n| !n.is_whitespace()) {
            if let Some(end) = find(i + 1, &['*']) {
                out.push_str(&format!("<em>{}</em>", inline(&slice(i + 1, end), image)));
                i = end + 1;
                continue;
            }
        } else if c == '[' || (c == '!' && chars.get(i + 1) == Some(&'[')) {
            let open = if c == '!' { i + 1 } else { i };
            if let Some(close) = find(open + 1, &[']', '(']) {
                if let Some(end) = find(close + 2, &[')']) {
                    let label = slice(open + 1, close);
                    let target = slice(close + 2, end);
                    if c == '!' {
                        out.push_str(&image(target.trim(), &label));
                    } else {
                        out.push_str(&format!(
                            "<a href=\"{}\">{}</a>",
                            escape(target.trim()),
                            inline(&label, image)
                        ));
                    }
                    i = end + 1;
                    continue;
                }
            }
        }
        out.push_str(&escape(&c.to_string()));
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn no_image(src: &str, alt: &str) -> String {
        format!("[{alt}:{src}]")
    }

    #[test]
    fn a_table_with_alignment_becomes_an_html_table() {
        let md = "Intro text\nwraps here.\n\n| strategy | error (m) | n |\n|:--|--:|:-:|\n| static | 0.012 | `5` |\n| remesh | **0.004** | 17 |\n";
        let html = to_html(md, &no_image);
        assert!(html.contains("<p>Intro text wraps here.</p>"), "{html}");
        assert!(html.contains("<thead>\n<tr><th>strategy</th><th style=\"text-align:right\">error (m)</th><th style=\"text-align:center\">n</th></tr>"), "{html}");
        assert!(html.contains("<tr><td>static</td><td style=\"text-align:right\">0.012</td><td style=\"text-align:center\"><code>5</code></td></tr>"), "{html}");
        assert!(
            html.contains("<td style=\"text-align:right\"><strong>0.004</strong></td>"),
            "{html}"
        );
        assert_eq!(html.matches("<tr>").count(), 3);
    }

    #[test]
    fn headings_lists_code_links_and_escaping() {
        let md = "# Results\n\n- one *a*\n- two [docs](docs/x.md)\n  continued\n\n1. first\n2. second\n\n```toml\nx = \"<1>\"\n```\n\nA < B & ![plot](p.svg)\n\n---\n";
        let html = to_html(md, &no_image);
        assert!(html.contains("<h2>Results</h2>"), "{html}");
        assert!(html.contains("<ul>\n<li>one <em>a</em></li>\n<li>two <a href=\"docs/x.md\">docs</a> continued</li>\n</ul>"), "{html}");
        assert!(
            html.contains("<ol>\n<li>first</li>\n<li>second</li>\n</ol>"),
            "{html}"
        );
        assert!(
            html.contains(
                "<pre><code class=\"language-toml\">x = &quot;&lt;1&gt;&quot;</code></pre>"
            ),
            "{html}"
        );
        assert!(
            html.contains("<p>A &lt; B &amp; [plot:p.svg]</p>"),
            "{html}"
        );
        assert!(html.contains("<hr>"));
        assert!(!html.contains("<script"));
        assert_eq!(
            to_html("<script>x</script>", &no_image),
            "<p>&lt;script&gt;x&lt;/script&gt;</p>\n"
        );
        assert_eq!(
            inline("a * b and snake_case", &no_image),
            "a * b and snake_case"
        );
    }
}
