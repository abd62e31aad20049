//! `--scorm lesson.zip`: the lesson page as a SCORM 1.2 package (ADL SCORM 1.2 Content
//! Aggregation Model): `imsmanifest.xml` at the root naming one organization, one item and
//! one SCO resource whose launch file is the page (`index.html`), with the title and
//! description as inline IMS metadata. The page finds the LMS's `window.API` itself.
use crate::{Error, Result};
use std::path::Path;

/// The page's name inside the package (the SCO's launch resource).
pub const LAUNCH: &str = "index.html";

/// The package of `html` written to `path`.
pub fn write(path: &Path, html: &str, title: &str, description: &str) -> Result<()> {
    let manifest = manifest(title, description);
    let bytes = super::zip::zip(&[
        ("imsmanifest.xml", manifest.as_bytes()),
        (LAUNCH, html.as_bytes()),
    ])
    .map_err(|e| Error::io(path, e))?;
    std::fs::write(path, bytes).map_err(|e| Error::io(path, e))
}

/// `imsmanifest.xml` for a one-page package.
pub fn manifest(title: &str, description: &str) -> String {
    let t = xml_escape(title);
    let description = if description.is_empty() {
        String::new()
    } else {
        format!(
            "\n        <imsmd:description><imsmd:langstring xml:lang=\"en\">{}</imsmd:langstring></imsmd:description>",
            xml_escape(description)
        )
    };
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<manifest identifier="glview-lesson" version="1.0"
    xmlns="http://www.imsproject.org/xsd/imscp_rootv1p1p2"
    xmlns:adlcp="http://www.adlnet.org/xsd/adlcp_rootv1p2"
    xmlns:imsmd="http://www.imsglobal.org/xsd/imsmd_rootv1p2p1"
    xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
    xsi:schemaLocation="http://www.imsproject.org/xsd/imscp_rootv1p1p2 imscp_rootv1p1p2.xsd http://www.imsglobal.org/xsd/imsmd_rootv1p2p1 imsmd_rootv1p2p1.xsd http://www.adlnet.org/xsd/adlcp_rootv1p2 adlcp_rootv1p2.xsd">
  <metadata>
    <schema>ADL SCORM</schema>
    <schemaversion>1.2</schemaversion>
    <imsmd:lom>
      <imsmd:general>
        <imsmd:title><imsmd:langstring xml:lang="en">{t}</imsmd:langstring></imsmd:title>{description}
      </imsmd:general>
    </imsmd:lom>
  </metadata>
  <organizations default="glview-organization">
    <organization identifier="glview-organization">
      <title>{t}</title>
      <item identifier="glview-item" identifierref="glview-page" isvisible="true">
        <title>{t}</title>
      </item>
    </organization>
  </organizations>
  <resources>
    <resource identifier="glview-page" type="webcontent" adlcp:scormtype="sco" href="{LAUNCH}">
      <file href="{LAUNCH}"/>
    </resource>
  </resources>
</manifest>
"#
    )
}

/// Text as XML character data or an attribute value; control characters XML 1.0 forbids
/// are dropped.
pub(crate) fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 => {}
            c => out.push(c),
        }
    }
    out
}
