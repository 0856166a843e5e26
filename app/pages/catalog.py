"""Page: catalog — browse and filter parts, read their sources, upload and merge your own CSV."""

from __future__ import annotations

import pandas as pd
import streamlit as st

from budget.catalog.io import parts_to_csv_text
from budget.catalog.schema import GRADES, PART_COLUMNS
from budget.check import PARAM_NAMES

import components as c
from page_frame import run_page
from upload_check import MAX_UPLOAD_BYTES, UploadCheck, check_upload


@st.cache_resource(show_spinner="Validating the upload …", max_entries=8)
def _check(data: bytes, name: str) -> UploadCheck:
    return check_upload(data, name)


def catalog_frame(parts: dict, shipped_ids: set[str], user_ids: set[str]) -> pd.DataFrame:
    """Parts as rows in the canonical column order, with where each row comes from."""
    rows = []
    for pid, p in parts.items():
        row = p.model_dump()
        row["origin"] = ("shipped" if pid not in user_ids else
                         "yours (replaces shipped)" if pid in shipped_ids else "yours")
        rows.append(row)
    lead = ["part_id", "vendor", "model", "grade"]
    cols = lead + ["origin"] + [k for k in PART_COLUMNS if k not in lead]
    return pd.DataFrame(rows, columns=cols)


def _filters(frame: pd.DataFrame) -> pd.DataFrame:
    left, mid, right = st.columns([2, 2, 1])
    grades = left.multiselect("grades", GRADES, default=list(GRADES), key="cat_grades")
    text = mid.text_input("search part id, vendor or model", key="cat_search").strip().lower()
    only_spec = right.checkbox("only parts with error figures", key="cat_only_specified",
                               help="hide parts whose datasheet figures are all empty (verdict 'unknown')")
    keep = frame["grade"].isin(grades)
    if text:
        hay = (frame["part_id"] + " " + frame["vendor"] + " " + frame["model"]).str.lower()
        keep &= hay.str.contains(text, regex=False)
    if only_spec:
        keep &= frame[list(PARAM_NAMES)].notna().any(axis=1)
    return frame[keep]


def _details(frame: pd.DataFrame) -> None:
    if frame.empty:
        return
    pid = st.selectbox("sources and notes of part", frame["part_id"].tolist(), key="cat_detail")
    row = frame.set_index("part_id").loc[pid]
    st.markdown(f"**{pid}** — {row['vendor']} {row['model']} · grade **{row['grade']}** · {row['origin']}")
    st.markdown(f"**Source:** {row['source']}")
    if row["notes"]:
        st.markdown(f"**Notes:** {row['notes']}")
    given = {k: row[k] for k in PART_COLUMNS if k in row.index and k not in ("part_id", "source", "notes")
             and pd.notna(row[k]) and row[k] != ""}
    st.dataframe(pd.DataFrame({"column": list(given), "value": [str(v) for v in given.values()]}),
                 hide_index=True, key="cat_detail_table")


#: Session-state key of what the last merge did (shown under the upload until the next one).
MERGE_NOTE_KEY = "cat_merge_note"


def merged_parts(before: dict, parts: dict) -> tuple[dict, list[str]]:
    """This session's parts after merging ``parts`` into ``before``: the parts merged before are
    kept, a part of ``parts`` with an id already merged replaces it. → (parts, replaced ids)."""
    replaced = [pid for pid in parts if pid in before]
    return {**before, **parts}, replaced


def merge_note(filename: str, parts: dict, replaced: list[str]) -> str:
    """What a merge did, in one line: how many parts were added and which earlier ones it replaced."""
    text = f"{filename}: merged {len(parts)} part{'s' if len(parts) != 1 else ''}"
    if replaced:
        text += (f"; replaced the part{'s' if len(replaced) > 1 else ''} you merged before with the same id: "
                 f"{', '.join(replaced)}")
    return text + "."


def _merge(parts: dict, filename: str) -> None:
    merged, replaced = merged_parts(c.user_parts(), parts)
    st.session_state[c.USER_PARTS_KEY] = merged
    st.session_state[MERGE_NOTE_KEY] = merge_note(filename, parts, replaced)


def _unmerge() -> None:
    st.session_state.pop(c.USER_PARTS_KEY, None)
    st.session_state.pop(MERGE_NOTE_KEY, None)


def _upload(shipped_ids: set[str]) -> None:
    st.subheader("Add your own parts")
    st.markdown("A CSV with the columns of `catalog/parts.csv` (`part_id`, `grade` and `source` required; "
                "empty cell = not in the datasheet). A row whose `part_id` is already in the catalog "
                "replaces it for this session; each merge adds to the parts merged before (a later upload of the "
                "same id replaces it). Nothing is merged until the whole file is valid.")
    up = st.file_uploader(f"parts CSV (at most {MAX_UPLOAD_BYTES // 1_000_000} MB)", type=["csv"],
                          key="cat_upload", max_upload_size=MAX_UPLOAD_BYTES // 1_000_000)
    if up is not None:
        res = _check(up.getvalue(), up.name)
        if res.ok:
            new = [p for p in res.parts if p not in shipped_ids]
            st.success(f"{res.filename}: {len(res.parts)} parts valid — {len(new)} new, "
                       f"{len(res.parts) - len(new)} replacing shipped parts.", icon=":material/check_circle:")
            st.button(f"Merge {len(res.parts)} parts into this session's catalog", key="cat_merge",
                      on_click=_merge, args=(res.parts, res.filename), type="primary",
                      help="added to the parts merged before; a part with an id merged before replaces it")
        else:
            more = " (listing stopped early)" if res.truncated else ""
            st.error(f"{res.filename}: {len(res.errors)} problem(s){more}; nothing was merged. "
                     f"First: {res.errors[0]}", icon=":material/error:")
            st.dataframe(pd.DataFrame(res.error_rows()), hide_index=True, key="cat_upload_errors")
    user = c.user_parts()
    if note := st.session_state.get(MERGE_NOTE_KEY):
        st.success(note, icon=":material/check_circle:")
    if user:
        st.info(f"Merged in this session: {len(user)} of your parts ({', '.join(sorted(user))}).",
                icon=":material/info:")
        st.button("Remove my parts", key="cat_unmerge", on_click=_unmerge)


def render() -> None:
    st.title("IMU catalog")
    shipped = c.shipped_catalog()
    merged = c.session_catalog()
    frame = catalog_frame(merged, set(shipped), set(c.user_parts()))
    shown = _filters(frame)
    st.caption(f"{len(shown)} of {len(frame)} parts · datasheet units (column names carry the unit) · "
               "empty = not specified by the datasheet, never assumed")
    st.dataframe(shown, hide_index=True, key="cat_table",
                 column_config={"source": st.column_config.TextColumn(width="large"),
                                "notes": st.column_config.TextColumn(width="large")})
    _details(shown)
    with st.expander("Grades: typical errors per grade (seed 004 Tables 3–4)"):
        st.dataframe(pd.DataFrame([g.model_dump() for g in c.grades().values()]), hide_index=True,
                     key="cat_grades_table")
    _upload(set(shipped))
    st.download_button("Download the merged catalog (CSV)", data=parts_to_csv_text(merged),
                       file_name="parts_merged.csv", mime="text/csv", key="cat_download")


run_page(render)
