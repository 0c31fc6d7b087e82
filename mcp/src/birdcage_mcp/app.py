# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""The MCP server object: lists the tools the rotator supports, and gives every failure a short
reason (a bad argument, rotctld's refusal, an unexpected error), never a bare "Error executing tool"."""

from __future__ import annotations

import functools
import logging
from typing import Any

from mcp.server import NotificationOptions
from mcp.server.mcpserver import Context, MCPServer
from mcp.server.mcpserver.exceptions import ToolError, UnexpectedToolError
from mcp.server.stdio import stdio_server
from mcp_types import Tool
from pydantic import ValidationError

from .rotator import ALL_TOOLS, Birdcage
from .rotctld import RotctldError
from .sky import Sky

logger = logging.getLogger(__name__)

# pydantic's wording for the checks the tools' schemas make, as a short phrase after the field's name.
SHORT_REASONS = {
    "missing": "is required",
    "float_parsing": "must be a number",
    "float_type": "must be a number",
    "finite_number": "must be a finite number",
    "int_parsing": "must be a whole number",
    "int_type": "must be a whole number",
    "int_from_float": "must be a whole number",
    "bool_parsing": "must be true or false",
    "bool_type": "must be true or false",
    "string_type": "must be a string",
}


def shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 32 else text[:29] + "..."


def validation_message(tool: str, error: ValidationError) -> str:
    """One clause per bad argument, e.g. `move_to: azimuth must be a number, got 'north'`."""
    clauses = []
    for item in error.errors(include_url=False):
        field = ".".join(str(part) for part in item["loc"]) or "arguments"
        reason = SHORT_REASONS.get(item["type"]) or item["msg"].replace("Input should be", "must be")
        clause = f"{field} {reason}"
        if item["type"] != "missing":
            clause += f", got {shown(item.get('input'))}"
        clauses.append(clause)
    return f"{tool}: " + "; ".join(clauses)


def tool_errors(function):
    """Turns a rotctld failure into the tool's error text."""

    @functools.wraps(function)
    async def wrapper(*args, **kwargs):
        try:
            return await function(*args, **kwargs)
        except RotctldError as error:
            raise ToolError(str(error)) from None

    return wrapper


class BirdcageServer(MCPServer):
    def __init__(self, bird: Birdcage, sky: Sky, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.bird = bird
        self.sky = sky
        self._listed: frozenset[str] | None = None  # what the client was last shown

    @staticmethod
    def ordered(offer: frozenset[str] | None) -> list[str]:
        return [name for name in ALL_TOOLS if offer is None or name in offer]

    async def list_tools(self) -> list[Tool]:
        """The tools the rotator supports (Birdcage.offer); all of them while rotctld cannot be asked,
        each then failing with its reason. A tool left out still answers when called by name."""
        offer = await self.bird.offer()
        self._listed = offer
        return [tool for tool in await super().list_tools() if offer is None or tool.name in offer]

    async def call_tool(self, name: str, arguments: dict[str, Any], context: Context | None = None) -> Any:
        try:
            return await super().call_tool(name, arguments, context)
        except UnexpectedToolError as error:
            cause = error.__cause__
            logger.exception("tool %s failed unexpectedly", name)
            raise ToolError(f"{name} failed: {type(cause).__name__}: {cause}" if cause else str(error)) from cause
        except ToolError as error:
            if isinstance(error.__cause__, ValidationError):
                raise ToolError(validation_message(name, error.__cause__)) from None
            raise
        finally:
            await self._announce_offer_change(context)

    async def _announce_offer_change(self, context: Context | None) -> None:
        """After a reconnect rotctld may front another rotator: tell the client when its tools differ."""
        if context is None or self._listed is None:
            return
        try:
            offer = await self.bird.offer()
        except Exception:  # the tool's own answer matters more than this notice
            return
        if offer is not None and offer != self._listed:
            self._listed = offer
            try:
                await context.session.send_tool_list_changed()
            except Exception as error:
                logger.info("could not announce the changed tool list: %s", error)

    async def run_stdio_async(self) -> None:
        async with stdio_server() as (read_stream, write_stream):
            await self._lowlevel_server.run(
                read_stream, write_stream,
                self._lowlevel_server.create_initialization_options(NotificationOptions(tools_changed=True)))
