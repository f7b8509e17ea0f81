"""The report: its document model (Markdown and PDF), figures, text, the many-body runs, and the build.

May import every package but ``grading`` and the CLI.
"""
