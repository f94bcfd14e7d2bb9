"""Pages and figures: one self-contained HTML page per campaign or run directory (``page``),
a flight's files (``flight``) and the figure plumbing they share (``figures``).  Campaign
kinds register their own page (``page.register_page``); this package imports no kind."""
